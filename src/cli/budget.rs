//! The input budget's flags (`--max-file-mb`, `--max-texture-mpix`, `--max-texture-mpix-total`,
//! `--max-instances`, `--max-triangles`, `--allow-outside-uris`): every command takes them, and
//! they are installed as the process's [`luz::files::InputBudget`] before the command runs.

use clap::Args;
use luz::files::{InputBudget, MIB, MPIX};

const D: InputBudget = InputBudget::DEFAULT;

#[derive(Args, Debug, Clone)]
pub struct BudgetArgs {
    /// Largest input file read (scene, OBJ, MTL, glTF, GLB, glTF buffer, image), in MiB; a
    /// glTF buffer's byteLength too. Default 256.
    #[arg(long, global = true, value_name = "MIB", value_parser = clap::value_parser!(u64).range(1..=(1 << 24)))]
    pub max_file_mb: Option<u64>,
    /// Most pixels of one decoded texture, in Mpix of 1024 × 1024 pixels (checked from the
    /// image's header before decoding). Default 64 (8192 × 8192).
    #[arg(long, global = true, value_name = "MPIX", value_parser = clap::value_parser!(u64).range(1..=(1 << 20)))]
    pub max_texture_mpix: Option<u64>,
    /// Most pixels of all a scene's textures together, in Mpix (each image once, checked from
    /// the headers before any is decoded). Default 256.
    #[arg(long, global = true, value_name = "MPIX", value_parser = clap::value_parser!(u64).range(1..=(1 << 24)))]
    pub max_texture_mpix_total: Option<u64>,
    /// Most mesh instances of one glTF file (one per node and primitive). Default 10000.
    #[arg(long, global = true, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_instances: Option<u64>,
    /// Most triangles one model file may expand into: a glTF's meshes baked once per instance,
    /// an OBJ's faces (n − 2 for a face of n corners, counted before they are built). Default
    /// 16777216 (2^24).
    #[arg(long, global = true, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    pub max_triangles: Option<u64>,
    /// Let glTF URIs name files outside the model's folder (absolute paths, `..`, links out).
    #[arg(long, global = true)]
    pub allow_outside_uris: bool,
}

impl BudgetArgs {
    /// The budget: the defaults with the flags given.
    pub fn budget(&self) -> InputBudget {
        let usize_of = |v: u64| usize::try_from(v).unwrap_or(usize::MAX);
        InputBudget {
            max_file_bytes: self.max_file_mb.map_or(D.max_file_bytes, |m| m * MIB),
            max_texture_pixels: self
                .max_texture_mpix
                .map_or(D.max_texture_pixels, |m| m * MPIX),
            max_texture_pixels_total: self
                .max_texture_mpix_total
                .map_or(D.max_texture_pixels_total, |m| m * MPIX),
            max_instances: self.max_instances.map_or(D.max_instances, usize_of),
            max_triangles: self.max_triangles.map_or(D.max_triangles, usize_of),
            allow_outside_uris: self.allow_outside_uris,
        }
    }
}
