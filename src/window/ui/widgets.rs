//! Widgets that edit a copy of a value and write it back only on a user edit, within the valid range.

use super::*;

// ---------------------------------------------------------------------------------------------
// Widgets that edit a copy and write back only on a user edit, within the valid range.

/// Writes `x` into `v` when the user `changed` it and it is finite; clamped to `range`.
pub(super) fn commit(v: &mut f32, x: f32, range: &RangeInclusive<f32>, changed: bool) -> bool {
    if !changed || !x.is_finite() {
        return false;
    }
    let x = x.clamp(*range.start(), *range.end());
    if x == *v {
        return false;
    }
    *v = x;
    true
}

/// A drag value in `range` (ends may be infinite); the speed follows the value's magnitude.
pub(super) fn drag(ui: &mut Ui, v: &mut f32, range: RangeInclusive<f32>) -> bool {
    let speed = (v.abs() * 0.01).max(0.005);
    drag_speed(ui, v, range, speed)
}

pub(super) fn drag_speed(ui: &mut Ui, v: &mut f32, range: RangeInclusive<f32>, speed: f32) -> bool {
    let mut x = *v;
    let r = ui.add(
        DragValue::new(&mut x)
            .range(range.clone())
            .clamp_existing_to_range(false)
            .speed(speed)
            .max_decimals(4),
    );
    commit(v, x, &range, r.changed())
}

/// A slider in a finite `range`, logarithmic if asked.
pub(super) fn slider(ui: &mut Ui, v: &mut f32, range: RangeInclusive<f32>, log: bool) -> bool {
    let mut x = *v;
    let r = ui.add(
        Slider::new(&mut x, range.clone())
            .logarithmic(log)
            .clamping(SliderClamping::Edits)
            .max_decimals(4),
    );
    commit(v, x, &range, r.changed())
}

/// A [0, 1] parameter.
pub(super) fn unit(ui: &mut Ui, v: &mut f32) -> bool {
    slider(ui, v, 0.0..=1.0, false)
}

/// A drag value plus a logarithmic slider for a non-negative quantity (intensities).
pub(super) fn intensity(ui: &mut Ui, v: &mut f32, slider_max: f32) -> bool {
    ui.horizontal(|ui| {
        let a = drag(ui, v, 0.0..=f32::INFINITY);
        let mut s = v.min(slider_max);
        let before = s;
        let b = slider(ui, &mut s, 0.0..=slider_max, true) && s != before;
        if b {
            *v = s;
        }
        a || b
    })
    .inner
}

pub(super) fn checkbox(ui: &mut Ui, v: &mut bool, text: &str) -> bool {
    let mut x = *v;
    let r = ui.checkbox(&mut x, text);
    if r.changed() && x != *v {
        *v = x;
        true
    } else {
        false
    }
}

/// Three drag values, each clamped to `range`.
pub(super) fn vec3(ui: &mut Ui, v: &mut Vec3, range: RangeInclusive<f32>, speed: f32) -> bool {
    ui.horizontal(|ui| {
        let mut changed = false;
        for (i, axis) in ["x", "y", "z"].into_iter().enumerate() {
            let mut x = v[i];
            let r = ui.add(
                DragValue::new(&mut x)
                    .range(range.clone())
                    .clamp_existing_to_range(false)
                    .speed(speed)
                    .max_decimals(4)
                    .prefix(format!("{axis} ")),
            );
            changed |= commit(&mut v[i], x, &range, r.changed());
        }
        changed
    })
    .inner
}

/// A unit direction: three components, normalised on edit; an edit that would make it zero
/// (or, with `max_y`, point above that y) is refused.
pub(super) fn direction(ui: &mut Ui, v: &mut Vec3, max_y: Option<f32>) -> bool {
    let mut x = *v;
    if !vec3(ui, &mut x, -1.0..=1.0, 0.01) {
        return false;
    }
    if let Some(m) = max_y {
        x.y = x.y.min(m);
    }
    match unit_vec(x) {
        Some(d) if max_y.is_none_or(|m| d.y <= m) && d != *v => {
            *v = d;
            true
        }
        _ => false,
    }
}

/// A linear RGB colour, each channel in [0, `max`] (`max` may be infinite): a colour picker
/// (scaled to the brightest channel when that exceeds 1) and three channels.
pub(super) fn color(ui: &mut Ui, v: &mut Vec3, max: f32) -> bool {
    ui.horizontal(|ui| {
        let mut changed = false;
        let scale = v.max_element().max(1.0);
        let mut shown = (*v / scale).to_array();
        if egui::color_picker::color_edit_button_rgb(ui, &mut shown).changed() {
            let c = (Vec3::from_array(shown) * scale).clamp(Vec3::ZERO, Vec3::splat(max));
            if c.is_finite() && c != *v {
                *v = c;
                changed = true;
            }
        }
        for (i, ch) in ["r", "g", "b"].into_iter().enumerate() {
            let mut x = v[i];
            let r = ui.add(
                DragValue::new(&mut x)
                    .range(0.0..=max)
                    .clamp_existing_to_range(false)
                    .speed(0.005 * scale)
                    .max_decimals(3)
                    .prefix(format!("{ch} ")),
            );
            changed |= commit(&mut v[i], x, &(0.0..=max), r.changed());
        }
        changed
    })
    .inner
}

/// A combo box over `options` (value, label).
pub(super) fn combo<T: PartialEq + Copy>(
    ui: &mut Ui,
    id_salt: impl egui::AsIdSalt,
    v: &mut T,
    options: &[(T, &str)],
) -> bool {
    let current = options
        .iter()
        .find(|(o, _)| o == v)
        .map_or("?", |(_, n)| *n);
    let mut x = *v;
    let mut changed = false;
    ComboBox::from_id_salt(id_salt)
        .selected_text(current)
        .show_ui(ui, |ui| {
            for (o, name) in options {
                changed |= ui.selectable_value(&mut x, *o, *name).changed();
            }
        });
    if changed && x != *v {
        *v = x;
        true
    } else {
        false
    }
}

/// A label in the first column of a two-column grid.
pub(super) fn row(ui: &mut Ui, label: &str, add: impl FnOnce(&mut Ui) -> bool) -> bool {
    ui.label(label);
    let changed = add(ui);
    ui.end_row();
    changed
}

pub(super) fn grid(
    ui: &mut Ui,
    id_salt: impl egui::AsIdSalt,
    add: impl FnOnce(&mut Ui) -> bool,
) -> bool {
    Grid::new(id_salt)
        .num_columns(2)
        .spacing([8.0, 4.0])
        .show(ui, add)
        .inner
}
