//! One material extension object of a glTF file, read with errors at
//! `materials[i].extensions.NAME.key`: numbers in a range, colours in [0, 1], texture infos that
//! must name an existing texture.

use std::path::Path;

use glam::Vec3;
use serde_json::{Map, Value};

use super::GltfError;

/// A number's allowed range.
#[derive(Clone, Copy)]
pub(super) enum Range {
    Unit,
    NonNegative,
    Positive,
}

impl Range {
    fn check(self, x: f64) -> Result<(), String> {
        let ok = match self {
            Range::Unit => (0.0..=1.0).contains(&x),
            Range::NonNegative => x >= 0.0,
            Range::Positive => x > 0.0,
        };
        if ok && x.is_finite() {
            return Ok(());
        }
        Err(match self {
            Range::Unit => format!("must be in [0, 1], got {x}"),
            Range::NonNegative => format!("must be ≥ 0, got {x}"),
            Range::Positive => format!("must be > 0, got {x}"),
        })
    }
}

/// One extension object of one material, with errors at `materials[i].extensions.NAME.key`.
pub(super) struct Ext<'a> {
    pub(super) obj: &'a Map<String, Value>,
    path: String,
    file: &'a Path,
}

impl<'a> Ext<'a> {
    pub(super) fn new(obj: &'a Map<String, Value>, path: String, file: &'a Path) -> Self {
        Self { obj, path, file }
    }

    /// Extension `name` of material `m` (`None` when absent); not an object is an error at
    /// `materials[i].extensions.NAME`.
    pub(super) fn of(
        m: &'a gltf::Material,
        name: &str,
        file: &'a Path,
    ) -> Result<Option<Self>, GltfError> {
        let Some(v) = m.extension_value(name) else {
            return Ok(None);
        };
        let path = format!("materials[{}].extensions.{name}", m.index().unwrap_or(0));
        match v.as_object() {
            Some(obj) => Ok(Some(Self::new(obj, path, file))),
            None => Err(GltfError {
                file: file.to_path_buf(),
                path,
                reason: "expected an object".into(),
            }),
        }
    }

    pub(super) fn err(&self, key: &str, reason: String) -> GltfError {
        GltfError {
            file: self.file.to_path_buf(),
            path: format!("{}.{key}", self.path),
            reason,
        }
    }

    pub(super) fn number(&self, key: &str, default: f32, range: Range) -> Result<f32, GltfError> {
        let Some(v) = self.obj.get(key) else {
            return Ok(default);
        };
        let x = v
            .as_f64()
            .ok_or_else(|| self.err(key, format!("expected a number, got {v}")))?;
        range.check(x).map_err(|r| self.err(key, r))?;
        Ok(x as f32)
    }

    pub(super) fn color(&self, key: &str, default: Vec3) -> Result<Vec3, GltfError> {
        let Some(v) = self.obj.get(key) else {
            return Ok(default);
        };
        let items = v
            .as_array()
            .filter(|a| a.len() == 3)
            .ok_or_else(|| self.err(key, format!("expected 3 numbers, got {v}")))?;
        let mut c = [0.0f32; 3];
        for (k, item) in items.iter().enumerate() {
            let x = item.as_f64().ok_or_else(|| {
                self.err(
                    &format!("{key}[{k}]"),
                    format!("expected a number, got {item}"),
                )
            })?;
            Range::Unit
                .check(x)
                .map_err(|r| self.err(&format!("{key}[{k}]"), r))?;
            c[k] = x as f32;
        }
        Ok(Vec3::from(c))
    }

    /// Whether any of `keys` is a texture info naming an existing texture (an error when it
    /// names none or has no index).
    pub(super) fn has_textures(&self, keys: &[&str], textures: usize) -> Result<bool, GltfError> {
        let mut any = false;
        for key in keys {
            let Some(info) = self.obj.get(*key) else {
                continue;
            };
            match info.get("index").and_then(|v| v.as_u64()) {
                Some(t) if (t as usize) < textures => any = true,
                Some(t) => {
                    return Err(self.err(
                        &format!("{key}.index"),
                        format!("texture {t} does not exist (the file has {textures})"),
                    ))
                }
                None => {
                    return Err(self.err(key, "expected a texture info with an \"index\"".into()))
                }
            }
        }
        Ok(any)
    }
}
