//! Maps a position in JSON text (line and column, as serde_json reports parse errors) to the
//! JSON pointer of the value there, so errors in scenes built from Python dicts name the field.

enum Frame {
    Object { key: Option<String> },
    Array { index: usize, started: bool },
}

/// The JSON pointer of the innermost value being read at (`line`, `column`), both 1-based.
pub fn pointer_at(text: &str, line: usize, column: usize) -> String {
    let mut offset = 0usize;
    for (i, l) in text.split_inclusive('\n').enumerate() {
        if i + 1 == line {
            offset += l
                .char_indices()
                .nth(column.saturating_sub(1))
                .map_or(l.len(), |(b, _)| b);
            break;
        }
        offset += l.len();
    }
    let bytes = text.as_bytes();
    let end = offset.min(bytes.len());
    let mut stack: Vec<Frame> = Vec::new();
    let mut i = 0;
    // Whether the last string read in an object was in key position.
    let mut expecting_key = false;
    while i < end {
        let c = bytes[i];
        match c {
            b'{' => {
                mark_array_value(&mut stack);
                stack.push(Frame::Object { key: None });
                expecting_key = true;
            }
            b'[' => {
                mark_array_value(&mut stack);
                stack.push(Frame::Array {
                    index: 0,
                    started: false,
                });
            }
            b'}' | b']' => {
                stack.pop();
                expecting_key = false;
            }
            b',' => match stack.last_mut() {
                Some(Frame::Array { index, .. }) => *index += 1,
                Some(Frame::Object { .. }) => expecting_key = true,
                None => {}
            },
            b':' => expecting_key = false,
            b'"' => {
                let start = i + 1;
                let mut j = start;
                while j < bytes.len() && bytes[j] != b'"' {
                    j += if bytes[j] == b'\\' { 2 } else { 1 };
                }
                let s = &text[start..j.min(bytes.len())];
                if expecting_key {
                    if let Some(Frame::Object { key }) = stack.last_mut() {
                        *key = Some(s.replace("~", "~0").replace('/', "~1"));
                    }
                } else {
                    mark_array_value(&mut stack);
                }
                i = j;
            }
            b' ' | b'\t' | b'\r' | b'\n' => {}
            _ => mark_array_value(&mut stack),
        }
        i += 1;
    }
    let mut out = String::new();
    for f in &stack {
        match f {
            Frame::Object { key: Some(k) } => {
                out.push('/');
                out.push_str(k);
            }
            Frame::Array {
                index,
                started: true,
            } => out.push_str(&format!("/{index}")),
            _ => {}
        }
    }
    if out.is_empty() {
        out.push('/');
    }
    out
}

fn mark_array_value(stack: &mut [Frame]) {
    if let Some(Frame::Array { started, .. }) = stack.last_mut() {
        *started = true;
    }
}

/// The `name` of the scene object (a mesh, material, light ...) that `pointer` lies in.
pub fn object_name(text: &str, pointer: &str) -> String {
    let parts: Vec<&str> = pointer.split('/').skip(1).take(2).collect();
    if parts.len() < 2 {
        return String::new();
    }
    let Ok(v) = serde_json::from_str::<serde_json::Value>(text) else {
        return String::new();
    };
    v.pointer(&format!("/{}/{}", parts[0], parts[1]))
        .and_then(|o| o.get("name"))
        .and_then(|n| n.as_str())
        .unwrap_or_default()
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(text: &str) -> String {
        let e = serde_json::from_str::<crate::scene::SceneDesc>(text).unwrap_err();
        pointer_at(text, e.line(), e.column())
    }

    #[test]
    fn names_the_field() {
        let t = r#"{"camera": {"fov": 0.5}, "meshes": [{"name": "a", "positions": [], "indices": []},
            {"name": "b", "positions": [[0,0,0]], "indices": [[0, 0, "x"]]}]}"#;
        assert_eq!(at(t), "/meshes/1/indices/0/2");
        let t = r#"{"camera": {"fov": 0.5, "bogus": 1}}"#;
        assert_eq!(at(t), "/camera/bogus");
        let t =
            r#"{"camera": {}, "lights": [{"type": "point", "position": [0,0,0], "power": "x"}]}"#;
        // Internally tagged enums are buffered by serde: the error points at the whole object.
        assert_eq!(at(t), "/lights/0");
        assert_eq!(
            object_name(r#"{"meshes": [{"name": "m"}]}"#, "/meshes/0/indices"),
            "m"
        );
    }
}
