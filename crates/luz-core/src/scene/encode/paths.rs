//! File paths in a saved scene: relative to the scene's folder when they share more than the
//! root, else absolute.

use std::path::{Component, Path, PathBuf};

use crate::scene::Scene;

// ---------------------------------------------------------------------------------------------
// Paths.

/// The folder of the file a scene came from.
pub(super) fn source_dir(scene: &Scene) -> Option<&Path> {
    scene
        .source
        .as_deref()
        .map(|p| p.parent().unwrap_or(Path::new("")))
}

/// `dir` made absolute, with symbolic links resolved when it exists.
pub(super) fn canonical_dir(dir: &Path) -> PathBuf {
    dir.canonicalize().unwrap_or_else(|_| absolute(dir))
}

/// `p` made absolute and lexically normalised (no `.`, `..` resolved), without touching the
/// file system.
pub(super) fn absolute(p: &Path) -> PathBuf {
    let p = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let mut out = PathBuf::new();
    for c in p.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                if !out.pop() {
                    out.push(c);
                }
            }
            c => out.push(c),
        }
    }
    out
}

/// A file's path as written in a scene file in the (canonical) folder `dir`: relative to `dir`
/// when the two share more than the file-system root, else absolute. The file's folder is
/// resolved (symbolic links included) but not the file name itself, so a link keeps its name
/// and extension.
pub(super) fn file_path(file: &Path, dir: Option<&Path>) -> String {
    let parent = match file.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let mut target = canonical_dir(parent);
    if let Some(name) = file.file_name() {
        target.push(name);
    }
    let show = |p: &Path| p.to_string_lossy().into_owned();
    let Some(dir) = dir else {
        return show(&target);
    };
    let t: Vec<Component> = target.components().collect();
    let d: Vec<Component> = dir.components().collect();
    let common = t.iter().zip(&d).take_while(|(a, b)| a == b).count();
    // Only the root (or a Windows prefix and root) in common: absolute.
    let shared_named = t[..common]
        .iter()
        .any(|c| matches!(c, Component::Normal(_)));
    if !shared_named || common == t.len() {
        return show(&target);
    }
    let mut parts: Vec<String> = vec!["..".to_string(); d.len() - common];
    parts.extend(
        t[common..]
            .iter()
            .map(|c| c.as_os_str().to_string_lossy().into_owned()),
    );
    parts.join("/")
}
