//! `luz info IMAGE`: an image's size and format and the provenance luz wrote into it.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;

#[derive(Args, Debug)]
pub struct InfoArgs {
    /// A PNG or EXR image.
    pub image: PathBuf,
}

pub fn run(a: InfoArgs) -> Result<ExitCode> {
    let img = luz::imageio::load(&a.image)?;
    let meta = luz::imageio::provenance::read(&a.image)?;
    println!(
        "{}: {} {}×{}",
        a.image.display(),
        img.format,
        img.width,
        img.height
    );
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
