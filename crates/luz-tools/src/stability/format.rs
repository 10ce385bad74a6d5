//! The aligned text table of a model's results.

use super::{ModelReport, SideStats};

fn fmt_big(v: f32) -> String {
    if v.is_nan() {
        "NaN".into()
    } else if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1e4 || v.abs() < 1e-3 {
        format!("{v:.2e}")
    } else {
        format!("{v:.4}")
    }
}

fn fmt_gain(g: Option<f32>) -> String {
    match g {
        None => "-".into(),
        Some(0.0) => "0".into(),
        Some(g) => format!("{g:.1e}"),
    }
}

const VARIANT_W: usize = 36;

fn side_header(name: &str) -> String {
    format!(
        "{:>4} {:>5} {:>5} {:>5} {:>9} {:>9} {:>8}",
        name.to_uppercase(),
        "NaN",
        "Inf",
        "neg",
        "max L",
        "max R",
        "gain"
    )
}

fn side_cells(s: &SideStats) -> String {
    format!(
        "{:>4} {:>5} {:>5} {:>5} {:>9} {:>9} {:>8}",
        "",
        s.nan,
        s.inf,
        s.negative,
        fmt_big(s.max_radiance),
        fmt_big(s.max_albedo),
        fmt_gain(s.energy_gain)
    )
}

/// The aligned table of one model.
pub fn format_model(m: &ModelReport) -> String {
    let mut out = format!("\n== {} — {}\n", m.model, m.claim);
    let Some(first) = m.rows.first() else {
        return out;
    };
    let mut header = format!("{:<VARIANT_W$} {:<10} {:>8} |", "variant", "claim", "cases");
    for s in &first.sides {
        header.push_str(&format!(" {} |", side_header(&s.side)));
    }
    if first.comparison.is_some() {
        header.push_str(&format!(" {:>8} {:>6}", "max rel", ">bound"));
    }
    out.push_str(&header);
    out.push('\n');
    out.push_str(&"-".repeat(header.chars().count()));
    out.push('\n');
    for r in &m.rows {
        let cases = r.sides.first().map(|s| s.cases).unwrap_or(0);
        let mut line = format!("{:<VARIANT_W$} {:<10} {:>8} |", r.variant, r.claim, cases);
        for s in &r.sides {
            line.push_str(&format!(" {} |", side_cells(s)));
        }
        if let Some(c) = &r.comparison {
            line.push_str(&format!(" {:>8.1e} {:>6}", c.max_rel, c.over_bound));
        }
        out.push_str(&line);
        out.push('\n');
    }
    out
}
