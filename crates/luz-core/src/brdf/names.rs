//! The names and codes of the selector enums and of the model kinds: one list each, from which
//! `ALL`, `name()`, `NAMED` and `from_name()` are generated (the scene format, the CLI, the
//! stability sweep and pipeline-variant names all use these).

use super::models::{Diffuse, Distribution, Fresnel, Geometry, Model};

/// `ALL`, `name()`, `NAMED` and `from_name()` of a selector enum from one list of (variant, name):
/// the one source of the names the scene format, the CLI, the stability sweep and pipeline-variant
/// names use (equal to the serde names; tested). The scene's environment methods use it too.
macro_rules! selector_names {
    ($t:ident { $($v:ident => $n:literal),+ $(,)? }) => {
        impl $t {
            /// Every value, in code order.
            pub const ALL: [$t; [$($n),+].len()] = [$($t::$v),+];
            /// (name, value) of every value, in code order.
            pub const NAMED: [(&'static str, $t); [$($n),+].len()] = [$(($n, $t::$v)),+];

            /// The name in scene files, on the command line and in reports (the serde name, where
            /// there is one).
            pub const fn name(self) -> &'static str {
                match self {
                    $($t::$v => $n),+
                }
            }

            /// The value called `name`.
            pub fn from_name(name: &str) -> Option<Self> {
                Self::NAMED.iter().find(|(n, _)| *n == name).map(|(_, v)| *v)
            }
        }
    };
}

pub(crate) use selector_names;

selector_names!(Distribution { Beckmann => "beckmann", Ggx => "ggx" });
selector_names!(Geometry {
    CookTorrance => "cook_torrance",
    SmithGgx => "smith_ggx",
    SmithGgxCorrelated => "smith_ggx_correlated",
    SchlickGgx => "schlick_ggx",
    SmithBeckmann => "smith_beckmann",
});
selector_names!(Fresnel {
    Schlick => "schlick",
    SchlickSg => "schlick_sg",
    Dielectric => "dielectric",
    Conductor => "conductor",
    ConductorExact => "conductor_exact",
});
selector_names!(Diffuse { Lambert => "lambert", Burley => "burley" });

/// A model without its parameters, in `BRDF_MODEL_*` code order: what a pipeline is specialised
/// for ([`Model::kind`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ModelKind {
    Lambert,
    Phong,
    BlinnPhong,
    CookTorrance,
    MetalRough,
    Principled,
    OrenNayar,
}

selector_names!(ModelKind {
    Lambert => "lambert",
    Phong => "phong",
    BlinnPhong => "blinn_phong",
    CookTorrance => "cook_torrance",
    MetalRough => "metal_rough",
    Principled => "principled",
    OrenNayar => "oren_nayar",
});

impl ModelKind {
    /// The GLSL `BRDF_MODEL_*` code (specialization constant `MODEL`, `sel.x`).
    pub const fn code(self) -> i32 {
        // The GLSL constants themselves (not `gpu::model_code`, which names them for the
        // GPU packing): names sit below the GPU code, never above it.
        use crate::glsl::brdf_models as m;
        match self {
            ModelKind::Lambert => m::BRDF_MODEL_LAMBERT,
            ModelKind::Phong => m::BRDF_MODEL_PHONG,
            ModelKind::BlinnPhong => m::BRDF_MODEL_BLINN_PHONG,
            ModelKind::CookTorrance => m::BRDF_MODEL_COOK_TORRANCE,
            ModelKind::MetalRough => m::BRDF_MODEL_METAL_ROUGH,
            ModelKind::Principled => m::BRDF_MODEL_PRINCIPLED,
            ModelKind::OrenNayar => m::BRDF_MODEL_OREN_NAYAR,
        }
    }

    /// Whether the model's D, G, F and diffuse lobe are selectable.
    pub const fn has_terms(self) -> bool {
        matches!(self, ModelKind::CookTorrance | ModelKind::MetalRough)
    }
}

impl Model {
    /// The model without its parameters.
    pub fn kind(&self) -> ModelKind {
        match self {
            Model::Lambert(_) => ModelKind::Lambert,
            Model::Phong(p) if p.blinn => ModelKind::BlinnPhong,
            Model::Phong(_) => ModelKind::Phong,
            Model::CookTorrance(_) => ModelKind::CookTorrance,
            Model::MetalRough(_) => ModelKind::MetalRough,
            Model::Principled(_) => ModelKind::Principled,
            Model::OrenNayar(_) => ModelKind::OrenNayar,
        }
    }

    /// The serde tag and the scene format's `model`: "lambert", "phong", "blinn_phong",
    /// "cook_torrance", "metal_rough", "principled", "oren_nayar" ([`ModelKind::name`]).
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// The model of kind `kind` with its default parameters.
    pub fn default_of(kind: ModelKind) -> Self {
        match kind {
            ModelKind::Lambert => Model::Lambert(Default::default()),
            ModelKind::Phong => Model::default_phong(false),
            ModelKind::BlinnPhong => Model::default_phong(true),
            ModelKind::CookTorrance => Model::CookTorrance(Default::default()),
            ModelKind::MetalRough => Model::MetalRough(Default::default()),
            ModelKind::Principled => Model::Principled(Default::default()),
            ModelKind::OrenNayar => Model::OrenNayar(Default::default()),
        }
    }
}
