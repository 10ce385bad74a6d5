//! `luz info IMAGE`: an image's size and format and the provenance luz wrote into it.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// A PNG or EXR image, or an SVG chart luz wrote.
    pub image: PathBuf,
}

pub fn run(a: InfoArgs) -> Result<ExitCode> {
    let svg = a
        .image
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("svg"));
    let meta = if svg {
        let meta = luz::imageio::provenance::read_svg(&a.image)
            .map_err(|e| anyhow::anyhow!("{}: {e}", a.image.display()))?;
        println!("{}: SVG", a.image.display());
        meta
    } else {
        let img = luz::imageio::load(&a.image)?;
        let meta = luz::imageio::provenance::read(&a.image)?;
        println!(
            "{}: {} {}×{}",
            a.image.display(),
            img.format,
            img.width,
            img.height
        );
        meta
    };
    if meta.is_empty() {
        println!("no provenance (not written by luz, or by a luz before provenance)");
    } else {
        let width = meta.entries.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
        for (k, v) in &meta.entries {
            println!("{k:width$}  {v}");
        }
    }
    Ok(ExitCode::SUCCESS)
}
