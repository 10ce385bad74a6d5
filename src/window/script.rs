//! Scripted viewer actions (`luz view --script`): what a user would do with the mouse, keyboard
//! and panels, at given frames, so tests and benchmarks can drive the viewer without input.

use std::path::PathBuf;

use anyhow::{anyhow, bail, Result};

use crate::color::Tonemap;
use crate::render::forward::DebugView;
use crate::scene::edit::ShadowEdit;
use crate::scene::ShadowMethod;
use crate::window::ui::compare::{CompareMode, ErrorMetric};

#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    Resize(u32, u32),
    Minimize,
    Restore,
    Exposure(f32),
    Tonemap(Tonemap),
    Panels(bool),
    Help(bool),
    Orbit(f32, f32),
    Zoom(f32),
    FrameAll,
    Reset,
    Vsync(bool),
    DebugView(DebugView),
    Screenshot(PathBuf),
    /// What dropping a file on the window does: a scene, a model or an environment.
    Open(PathBuf),
    /// Save the scene (with the current camera) as JSON.
    Save(PathBuf),
    /// Add N ranged point lights over the scene (`scene::edit::light_field`), as the lights
    /// panel's "Add many" does.
    AddLights(crate::scene::edit::LightField, u32),
    /// How A and B are shown (`compare_mode=split|difference|flip|toggle`).
    CompareMode(CompareMode),
    /// The split divider, 0..1 of the width (`compare_split=X`).
    CompareSplit(f32),
    /// Toggle mode: show the other side (the B key).
    CompareFlip,
    /// Make B a copy of A (the lab panel's "Duplicate the scene into B").
    CompareDuplicate,
    /// The error view against the CPU reference (`error_view=on|off`).
    ErrorView(bool),
    /// What the error view shows (`error_metric=relative|flip`).
    ErrorMetric(ErrorMetric),
    /// The lab panel's lobe plots of the selected material (`lobe_plots=on|off`).
    LobePlots(bool),
    /// Which side the panels and the scene-editing actions (exposure, tonemap) change
    /// (`compare_edit=a|b`).
    CompareEdit(bool),
    /// The shadow-map window showing light N, or closed (`shadow_map=N|off`).
    ShadowMap(Option<usize>),
    /// Read the maps back and write the shown light's picture (`shadow_map_save=PATH`).
    ShadowMapSave(PathBuf),
    /// Light N's Shadow rows in the lights panel: `light_shadow=N:off|on|hard|pcf|pcss` and
    /// `light_shadow_resolution=N:TEXELS`.
    LightShadow(usize, ShadowEdit),
}

/// The script text of a [`Action::LightShadow`] (for its errors).
pub fn light_shadow_text(light: usize, edit: ShadowEdit) -> String {
    match edit {
        ShadowEdit::Off => format!("light_shadow={light}:off"),
        ShadowEdit::On => format!("light_shadow={light}:on"),
        ShadowEdit::Method(m) => format!("light_shadow={light}:{}", m.name()),
        ShadowEdit::Resolution(r) => format!("light_shadow_resolution={light}:{r}"),
    }
}

pub use crate::scene::edit::MAX_ADDED_LIGHTS;

/// `FRAME:ACTION;FRAME:ACTION;…` → (frame, action) sorted by frame (stable).
pub fn parse(text: &str) -> Result<Vec<(u64, Action)>> {
    let mut out = Vec::new();
    for item in text.split(';').map(str::trim).filter(|s| !s.is_empty()) {
        let context = format!("script item {item:?}");
        let (frame, action) = numbered::<u64>(item, &context, "FRAME:ACTION", "a frame number")?;
        let action = parse_action(action.trim()).map_err(|e| anyhow!("{context}: {e}"))?;
        out.push((frame, action));
    }
    out.sort_by_key(|(f, _)| *f);
    Ok(out)
}

/// `N:REST` → (N, REST), N trimmed and parsed. The errors start with `context` and say what was
/// `expected` (no ':') or that N is not `number` ("a frame number").
fn numbered<'s, N: std::str::FromStr>(
    s: &'s str,
    context: &str,
    expected: &str,
    number: &str,
) -> Result<(N, &'s str)> {
    let (n, rest) = s
        .split_once(':')
        .ok_or_else(|| anyhow!("{context}: expected {expected}"))?;
    let n = n
        .trim()
        .parse()
        .map_err(|_| anyhow!("{context}: {n:?} is not {number}"))?;
    Ok((n, rest))
}

fn on_off(v: &str) -> Result<bool> {
    match v {
        "on" | "true" | "1" => Ok(true),
        "off" | "false" | "0" => Ok(false),
        _ => bail!("{v:?} is not on or off"),
    }
}

fn finite(v: &str) -> Result<f32> {
    let x: f32 = v.parse().map_err(|_| anyhow!("{v:?} is not a number"))?;
    if !x.is_finite() {
        bail!("{v:?} is not finite");
    }
    Ok(x)
}

fn parse_action(a: &str) -> Result<Action> {
    let (name, value) = match a.split_once('=') {
        Some((n, v)) => (n.trim(), Some(v.trim())),
        None => (a, None),
    };
    let need = || value.ok_or_else(|| anyhow!("{name} needs a value ({name}=…)"));
    Ok(match name {
        "resize" => {
            let v = need()?;
            let (w, h) = v
                .split_once('x')
                .ok_or_else(|| anyhow!("resize={v}: expected WIDTHxHEIGHT"))?;
            let parse = |s: &str| -> Result<u32> {
                let n: u32 = s.parse().map_err(|_| anyhow!("resize={v}: {s:?}"))?;
                if n > 16384 {
                    bail!("resize={v}: {n} is larger than 16384");
                }
                Ok(n)
            };
            Action::Resize(parse(w)?, parse(h)?)
        }
        "minimize" => Action::Minimize,
        "restore" => Action::Restore,
        "exposure" => Action::Exposure(finite(need()?)?),
        "tonemap" => {
            let v = need()?;
            let t = Tonemap::ALL
                .iter()
                .copied()
                .find(|t| t.name() == v)
                .ok_or_else(|| {
                    anyhow!(
                        "tonemap={v}: expected one of {}",
                        Tonemap::ALL.map(|t| t.name()).join(", ")
                    )
                })?;
            Action::Tonemap(t)
        }
        "panels" => Action::Panels(on_off(need()?)?),
        "help" => Action::Help(on_off(need()?)?),
        "vsync" => Action::Vsync(on_off(need()?)?),
        "orbit" => {
            let v = need()?;
            let (x, y) = v
                .split_once(',')
                .ok_or_else(|| anyhow!("orbit={v}: expected DX,DY in degrees"))?;
            Action::Orbit(finite(x)?, finite(y)?)
        }
        "zoom" => Action::Zoom(finite(need()?)?),
        "frame_all" => Action::FrameAll,
        "reset" => Action::Reset,
        "debug_view" => {
            let v = need()?;
            Action::DebugView(
                DebugView::from_name(v).ok_or_else(|| anyhow!("debug_view={v}: unknown view"))?,
            )
        }
        "screenshot" => Action::Screenshot(PathBuf::from(need()?)),
        "shadow_map" => match need()? {
            "off" => Action::ShadowMap(None),
            v => Action::ShadowMap(Some(v.parse().map_err(|_| {
                anyhow!("shadow_map={v}: expected a light index or off")
            })?)),
        },
        "shadow_map_save" => Action::ShadowMapSave(PathBuf::from(need()?)),
        "light_shadow" | "light_shadow_resolution" => {
            let v = need()?;
            let resolution = name == "light_shadow_resolution";
            let expected = if resolution {
                "LIGHT:TEXELS"
            } else {
                "LIGHT:off|on|hard|pcf|pcss"
            };
            let (light, what) =
                numbered::<usize>(v, &format!("{name}={v}"), expected, "a light index")?;
            let edit = match (resolution, what.trim()) {
                (true, n) => ShadowEdit::Resolution(
                    n.parse()
                        .map_err(|_| anyhow!("{name}={v}: {n:?} is not a number of texels"))?,
                ),
                (false, "off") => ShadowEdit::Off,
                (false, "on") => ShadowEdit::On,
                (false, m) => ShadowEdit::Method(
                    ShadowMethod::from_name(m)
                        .ok_or_else(|| anyhow!("{name}={v}: expected {expected}"))?,
                ),
            };
            Action::LightShadow(light, edit)
        }
        "open" => Action::Open(PathBuf::from(need()?)),
        "save" => Action::Save(PathBuf::from(need()?)),
        "add_lights" => {
            let v = need()?;
            let parsed = v.split_once(':').and_then(|(f, n)| {
                Some((
                    crate::scene::edit::LightField::from_name(f.trim())?,
                    n.trim()
                        .parse::<u32>()
                        .ok()
                        .filter(|&n| n <= MAX_ADDED_LIGHTS)?,
                ))
            });
            let (field, n) = parsed.ok_or_else(|| {
                anyhow!("add_lights={v}: expected grid:N or random:N, N at most {MAX_ADDED_LIGHTS}")
            })?;
            Action::AddLights(field, n)
        }
        "compare_mode" => {
            let v = need()?;
            Action::CompareMode(CompareMode::from_name(v).ok_or_else(|| {
                anyhow!("compare_mode={v}: expected split, difference, flip or toggle")
            })?)
        }
        "compare_split" => {
            let v = need()?;
            let x = finite(v)?;
            if !(0.0..=1.0).contains(&x) {
                bail!("compare_split={v}: expected a number from 0 to 1");
            }
            Action::CompareSplit(x)
        }
        "compare_flip" => Action::CompareFlip,
        "compare_duplicate" => Action::CompareDuplicate,
        "error_view" => Action::ErrorView(on_off(need()?)?),
        "lobe_plots" => Action::LobePlots(on_off(need()?)?),
        "compare_edit" => match need()? {
            "a" => Action::CompareEdit(false),
            "b" => Action::CompareEdit(true),
            v => bail!("compare_edit={v}: expected a or b"),
        },
        "error_metric" => match need()? {
            "relative" => Action::ErrorMetric(ErrorMetric::Relative),
            "flip" => Action::ErrorMetric(ErrorMetric::Flip),
            v => bail!("error_metric={v}: expected relative or flip"),
        },
        other => bail!(
            "unknown action {other:?} (resize, minimize, restore, exposure, tonemap, panels, help, \
             orbit, zoom, frame_all, reset, vsync, debug_view, screenshot, open, save, add_lights, \
             compare_mode, compare_split, compare_flip, compare_duplicate, error_view, error_metric, \
             lobe_plots, compare_edit, shadow_map, shadow_map_save, light_shadow, \
             light_shadow_resolution)"
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_every_action() {
        let s = parse(
            "20:exposure=1.5; 10:resize=800x600;30:tonemap=agx;31:panels=off;32:orbit=10,-5;\
             33:minimize;34:restore;35:debug_view=normal;36:screenshot=a.png;37:vsync=on;\
             38:add_lights=grid:256;39:add_lights=random:8",
        )
        .unwrap();
        use crate::scene::edit::LightField;
        assert_eq!(s[10], (38, Action::AddLights(LightField::Grid, 256)));
        assert_eq!(s[11], (39, Action::AddLights(LightField::Random, 8)));
        assert_eq!(s[0], (10, Action::Resize(800, 600)));
        assert_eq!(s[1], (20, Action::Exposure(1.5)));
        assert_eq!(s[2], (30, Action::Tonemap(Tonemap::Agx)));
        assert_eq!(s[3], (31, Action::Panels(false)));
        assert_eq!(s[4], (32, Action::Orbit(10.0, -5.0)));
        assert_eq!(s[7], (35, Action::DebugView(DebugView::Normal)));
        assert_eq!(s.len(), 12);
        let c = parse(
            "1:compare_mode=difference;2:compare_split=0.25;3:compare_flip;4:compare_duplicate;\
             5:error_view=on;6:error_metric=flip;7:lobe_plots=on;8:compare_edit=b",
        )
        .unwrap();
        assert_eq!(c[0].1, Action::CompareMode(CompareMode::Difference));
        assert_eq!(c[1].1, Action::CompareSplit(0.25));
        assert_eq!(c[2].1, Action::CompareFlip);
        assert_eq!(c[3].1, Action::CompareDuplicate);
        assert_eq!(c[4].1, Action::ErrorView(true));
        assert_eq!(c[5].1, Action::ErrorMetric(ErrorMetric::Flip));
        assert_eq!(c[6].1, Action::LobePlots(true));
        assert_eq!(c[7].1, Action::CompareEdit(true));
        let l = parse(
            "1:light_shadow=0:off;2:light_shadow=1:on;3:light_shadow=0:pcss;\
             4:light_shadow_resolution=2:512",
        )
        .unwrap();
        assert_eq!(l[0].1, Action::LightShadow(0, ShadowEdit::Off));
        assert_eq!(l[1].1, Action::LightShadow(1, ShadowEdit::On));
        assert_eq!(
            l[2].1,
            Action::LightShadow(0, ShadowEdit::Method(ShadowMethod::Pcss))
        );
        assert_eq!(l[3].1, Action::LightShadow(2, ShadowEdit::Resolution(512)));
    }

    #[test]
    fn rejects_bad_items_with_the_item_named() {
        for (bad, needle) in [
            ("resize=10x10", "FRAME:ACTION"),
            ("x:reset", "not a frame number"),
            ("1:resize=10", "WIDTHxHEIGHT"),
            ("1:exposure=nan", "not finite"),
            ("1:tonemap=filmic", "expected one of"),
            ("1:fly", "unknown action"),
            ("1:panels=maybe", "not on or off"),
            ("1:resize=99999x10", "larger than"),
            ("1:add_lights=spiral:4", "grid:N or random:N"),
            ("1:add_lights=grid:-1", "grid:N or random:N"),
            ("1:add_lights=grid:99999999", "at most 65536"),
            (
                "1:compare_mode=overlay",
                "split, difference, flip or toggle",
            ),
            ("1:compare_split=1.5", "from 0 to 1"),
            ("1:error_view=maybe", "not on or off"),
            ("1:error_metric=ssim", "relative or flip"),
            ("1:compare_edit=c", "a or b"),
            ("1:light_shadow=0", "expected LIGHT:off|on|hard|pcf|pcss"),
            (
                "1:light_shadow=0:soft",
                "expected LIGHT:off|on|hard|pcf|pcss",
            ),
            ("1:light_shadow=x:off", "\"x\" is not a light index"),
            (
                "1:light_shadow_resolution=0:big",
                "\"big\" is not a number of texels",
            ),
        ] {
            let e = parse(bad).unwrap_err().to_string();
            assert!(e.contains(needle), "{bad}: {e}");
        }
    }
}
