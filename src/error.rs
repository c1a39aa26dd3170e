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
    #[error("invalid render setting `{setting}`: {message}")]
    InvalidSetting { setting: String, message: String },
    #[error("internal error: {0}")]
    Internal(String),
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
