//! The JSON form of the scene IR: for tests, bug reports and shipping scenes between machines.

use crate::error::{Error, Result};
use crate::scene::{validate, SceneDesc};
use std::path::Path;

/// Parses and validates a scene from JSON text.
pub fn from_str(text: &str) -> Result<SceneDesc> {
    let scene: SceneDesc = serde_json::from_str(text).map_err(|e| Error::Json {
        line: e.line(),
        column: e.column(),
        message: e.to_string(),
    })?;
    validate(&scene)?;
    Ok(scene)
}

/// Reads, parses and validates a scene file.
pub fn load(path: impl AsRef<Path>) -> Result<SceneDesc> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    from_str(&text).map_err(|e| match e {
        Error::Json {
            line,
            column,
            message,
        } => Error::Io {
            path: path.display().to_string(),
            message: format!("line {line}, column {column}: {message}"),
        },
        other => other,
    })
}

/// Serialises a scene to pretty JSON.
pub fn to_string(scene: &SceneDesc) -> String {
    serde_json::to_string_pretty(scene).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TRI: &str = r#"{
        "camera": {"fov": 0.8},
        "materials": [{"type": "diffuse", "color": [0.5, 0.5, 0.5]}],
        "meshes": [{"name": "floor", "positions": [[0,0,0],[1,0,0],[0,1,0]], "indices": [[0,1,2]]}],
        "lights": [{"type": "point", "name": "lamp", "position": [0,0,1], "power": 100}]
    }"#;

    #[test]
    fn round_trip() {
        let s = from_str(TRI).unwrap();
        assert_eq!(s.meshes[0].name, "floor");
        let again = from_str(&to_string(&s)).unwrap();
        assert_eq!(s, again);
    }

    fn err_of(text: &str) -> String {
        from_str(text).unwrap_err().to_string()
    }

    #[test]
    fn errors_name_the_field() {
        let e = err_of(&TRI.replace("[0,1,2]", "[0,1,7]"));
        assert!(
            e.contains("/meshes/0/indices/0/2")
                && e.contains("floor")
                && e.contains("out of range"),
            "{e}"
        );
        let e = err_of(&TRI.replace("\"power\": 100", "\"power\": -1"));
        assert!(e.contains("/lights/0/power") && e.contains("lamp"), "{e}");
        let e = err_of(&TRI.replace("[[0,1,2]]", "[]"));
        assert!(
            e.contains("/meshes/0/indices") && e.contains("no triangles"),
            "{e}"
        );
        let e = err_of(&TRI.replace("\"fov\": 0.8", "\"fov\": 0.8, \"bogus\": 1"));
        assert!(e.contains("bogus") && e.contains("line"), "{e}");
        let e = err_of(&TRI.replace("\"type\": \"point\"", "\"type\": \"laser\""));
        assert!(e.contains("laser"), "{e}");
        let e = err_of(&TRI.replace("[0.5, 0.5, 0.5]", "{\"texture\": 3}"));
        assert!(e.contains("/materials/0/color/texture"), "{e}");
        let e = err_of(&TRI[..40]);
        assert!(e.contains("line"), "{e}");
    }

    #[test]
    fn nan_is_rejected_not_panicking() {
        let mut s = from_str(TRI).unwrap();
        s.meshes[0].positions[1][2] = f32::NAN;
        let e = validate(&s).unwrap_err().to_string();
        assert!(e.contains("/meshes/0/positions/1/2"), "{e}");
        s.meshes[0].positions[1][2] = 0.0;
        s.meshes[0].transform = [[0.0; 4]; 4];
        let e = validate(&s).unwrap_err().to_string();
        assert!(
            e.contains("/meshes/0/transform") && e.contains("singular"),
            "{e}"
        );
    }
}
