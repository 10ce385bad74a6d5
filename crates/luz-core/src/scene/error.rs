//! Scene errors. Every message reads `<file>: <json path>: <reason>`.

use std::fmt;
use std::path::{Path, PathBuf};

/// Why a scene could not be loaded. `Display` gives `<file>: <json path>: <reason>`; the JSON path
/// is `(root)` for the document as a whole.
#[derive(thiserror::Error, Debug)]
pub enum SceneError {
    /// The scene file itself could not be read (missing, unreadable, not UTF-8).
    #[error("{}: (root): {reason}", file.display())]
    Read { file: PathBuf, reason: String },
    /// The text is not valid JSON; `path` is where the reader was.
    #[error("{}: {path}: {reason} at line {line}, column {column}", file.display())]
    Syntax {
        file: PathBuf,
        path: String,
        line: u32,
        column: u32,
        reason: String,
    },
    /// Valid JSON, but not a valid scene (unknown field, wrong type, value out of range, …).
    #[error("{}: {path}: {reason}", file.display())]
    Invalid {
        file: PathBuf,
        path: String,
        reason: String,
    },
    /// An OBJ (or its MTL) referenced by the scene is missing or broken. `mesh_file` is the
    /// OBJ/MTL file at fault, `line` its 1-based line when known.
    #[error("{}: {path}: {}: {reason}", file.display(), Located(mesh_file, *line))]
    Mesh {
        file: PathBuf,
        path: String,
        mesh_file: PathBuf,
        line: Option<usize>,
        reason: String,
    },
}

struct Located<'a>(&'a Path, Option<usize>);

impl fmt::Display for Located<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.1 {
            Some(line) => write!(f, "{}:{line}", self.0.display()),
            None => write!(f, "{}", self.0.display()),
        }
    }
}

impl SceneError {
    /// The scene file, the JSON path and the reason: what every variant has.
    fn parts(&self) -> (&Path, &str, &str) {
        match self {
            SceneError::Read { file, reason } => (file, "(root)", reason),
            SceneError::Syntax {
                file, path, reason, ..
            }
            | SceneError::Invalid { file, path, reason }
            | SceneError::Mesh {
                file, path, reason, ..
            } => (file, path, reason),
        }
    }

    /// The scene file the error is about.
    pub fn file(&self) -> &Path {
        self.parts().0
    }

    /// The JSON path of the offending value, e.g. `lights[2].intensity`.
    pub fn json_path(&self) -> &str {
        self.parts().1
    }

    /// The reason alone, without file and path.
    pub fn reason(&self) -> &str {
        self.parts().2
    }
}

/// An error found while decoding, before the file name is attached.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Invalid {
    pub path: String,
    pub reason: String,
    /// Set for OBJ/MTL problems.
    pub mesh: Option<(PathBuf, Option<usize>)>,
}

impl Invalid {
    pub fn new(path: &str, reason: impl Into<String>) -> Self {
        Invalid {
            path: path.to_string(),
            reason: reason.into(),
            mesh: None,
        }
    }

    pub fn into_scene_error(self, file: &Path) -> SceneError {
        match self.mesh {
            None => SceneError::Invalid {
                file: file.to_path_buf(),
                path: self.path,
                reason: self.reason,
            },
            Some((mesh_file, line)) => SceneError::Mesh {
                file: file.to_path_buf(),
                path: self.path,
                mesh_file,
                line,
                reason: self.reason,
            },
        }
    }
}
