//! One material extension object of a glTF file, read with errors at
//! `materials[i].extensions.NAME.key`: numbers in a range, colours in [0, 1], texture infos that
//! must name an existing texture.

use std::path::Path;

use glam::Vec3;
use serde_json::{Map, Value};

use super::primitive::UvChoice;
use super::GltfError;

/// A number's allowed range.
#[derive(Clone, Copy)]
pub(super) enum Range {
    Unit,
    NonNegative,
    Positive,
    /// Any number a 32-bit float holds (an angle in radians).
    Finite,
}

impl Range {
    fn check(self, x: f64) -> Result<(), String> {
        let ok = match self {
            Range::Unit => (0.0..=1.0).contains(&x),
            Range::NonNegative => x >= 0.0,
            Range::Positive => x > 0.0,
            Range::Finite => x.abs() <= f32::MAX as f64,
        };
        if ok && x.is_finite() {
            return Ok(());
        }
        Err(match self {
            Range::Unit => format!("must be in [0, 1], got {x}"),
            Range::NonNegative => format!("must be ≥ 0, got {x}"),
            Range::Positive => format!("must be > 0, got {x}"),
            Range::Finite => format!("must be a finite number, got {x:e}"),
        })
    }
}

/// One extension object of one material, with errors at `materials[i].extensions.NAME.key`.
#[derive(Clone)]
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

    /// The texture info at `key` (`None` when absent): the texture's index, checked against the
    /// file's `count` textures, and the UVs it reads (`texCoord`, and `KHR_texture_transform`
    /// when present). Errors name `…key.index`, `…key.texCoord` and the transform's fields.
    pub(super) fn texture_info(
        &self,
        key: &str,
        count: usize,
    ) -> Result<Option<(usize, UvChoice)>, GltfError> {
        if !self.has_textures(&[key], count)? {
            return Ok(None);
        }
        let info = &self.obj[key];
        // has_textures checked the index.
        let index = info["index"].as_u64().unwrap_or(0) as usize;
        let set = |v: Option<&Value>, at: &str| -> Result<Option<u32>, GltfError> {
            match v {
                None => Ok(None),
                Some(v) => v
                    .as_u64()
                    .filter(|&s| s < 16)
                    .map(|s| Some(s as u32))
                    .ok_or_else(|| self.err(at, format!("expected a UV set 0–15, got {v}"))),
            }
        };
        let mut uv = UvChoice {
            set: set(info.get("texCoord"), &format!("{key}.texCoord"))?.unwrap_or(0),
            ..UvChoice::default()
        };
        if let Some(t) = info
            .get("extensions")
            .and_then(|x| x.get("KHR_texture_transform"))
        {
            let at = format!("{key}.extensions.KHR_texture_transform");
            let nums = |field: &str, n: usize| -> Result<Option<Vec<f32>>, GltfError> {
                let Some(v) = t.get(field) else {
                    return Ok(None);
                };
                let items: Option<Vec<f32>> = match (n, v) {
                    (1, v) => v.as_f64().map(|x| vec![x as f32]),
                    (_, Value::Array(a)) if a.len() == n => {
                        a.iter().map(|x| x.as_f64().map(|x| x as f32)).collect()
                    }
                    _ => None,
                };
                match items.filter(|xs| xs.iter().all(|x| x.is_finite())) {
                    Some(xs) => Ok(Some(xs)),
                    None => Err(self.err(
                        &format!("{at}.{field}"),
                        format!("expected {n} finite number(s), got {v}"),
                    )),
                }
            };
            if let Some(o) = nums("offset", 2)? {
                uv.offset = glam::Vec2::new(o[0], o[1]);
            }
            if let Some(r) = nums("rotation", 1)? {
                uv.rotation = r[0];
            }
            if let Some(s) = nums("scale", 2)? {
                uv.scale = glam::Vec2::new(s[0], s[1]);
            }
            if let Some(s) = set(t.get("texCoord"), &format!("{at}.texCoord"))? {
                uv.set = s;
            }
        }
        Ok(Some((index, uv)))
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
