//! Typed errors. Every error says where it came from: a JSON pointer into the scene IR
//! (which front ends map back to a USD prim path or a Blender object), or a file.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum Error {
    /// A value in the scene IR is invalid. `pointer` is a JSON pointer such as `/meshes/2/indices/7`;
    /// `object` is the name of the mesh, light or material it belongs to, when it has one.
    #[error("invalid scene at {pointer}{}: {message}", object_suffix(.object))]
    InvalidScene {
        pointer: String,
        object: String,
        message: String,
    },
    #[error("cannot parse scene JSON at line {line}, column {column}: {message}")]
    Json {
        line: usize,
        column: usize,
        message: String,
    },
    #[error("{path}: {message}")]
    Io { path: String, message: String },
    #[error("render cancelled")]
    Cancelled,
    /// `setting` is the setting's keyword (as Python and the stats name it); the command
    /// line reports it by its flag ([`Error::for_cli`]).
    #[error("invalid render setting `{setting}`: {message}")]
    InvalidSetting { setting: String, message: String },
    /// A setting the schema does not have (`render::settings`); `known` lists those it has.
    #[error("unknown render setting `{setting}` (the settings are: {known})")]
    UnknownSetting { setting: String, known: String },
    #[error("internal error: {0}")]
    Internal(String),
}

impl Error {
    /// The error as the command line reports it: a setting, named in the core by its keyword
    /// (`time_budget`, `width/height`), is named by its flag (`--time-budget`,
    /// `--width/--height`).
    pub fn for_cli(self) -> Error {
        match self {
            Error::InvalidSetting { setting, message } => Error::InvalidSetting {
                setting: setting
                    .split('/')
                    .map(|k| format!("--{}", k.replace('_', "-")))
                    .collect::<Vec<_>>()
                    .join("/"),
                message,
            },
            other => other,
        }
    }
}

fn object_suffix(object: &str) -> String {
    if object.is_empty() {
        String::new()
    } else {
        format!(" (`{object}`)")
    }
}

impl Error {
    pub fn scene(pointer: impl Into<String>, object: &str, message: impl Into<String>) -> Self {
        Error::InvalidScene {
            pointer: pointer.into(),
            object: object.to_string(),
            message: message.into(),
        }
    }
    pub fn io(path: impl AsRef<std::path::Path>, e: impl std::fmt::Display) -> Self {
        Error::Io {
            path: path.as_ref().display().to_string(),
            message: e.to_string(),
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[cfg(test)]
mod cli_name_tests {
    use super::Error;

    #[test]
    fn the_command_line_names_settings_by_their_flags() {
        let e = |s: &str| Error::InvalidSetting {
            setting: s.into(),
            message: "m".into(),
        };
        assert_eq!(
            e("time_budget").for_cli().to_string(),
            "invalid render setting `--time-budget`: m"
        );
        assert_eq!(
            e("width/height").for_cli().to_string(),
            "invalid render setting `--width/--height`: m"
        );
        assert_eq!(e("spp").to_string(), "invalid render setting `spp`: m");
    }
}
