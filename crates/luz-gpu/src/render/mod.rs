//! The GPU renderer: one file per pass. Passes record into a command buffer for a given target and
//! own no swapchain, so the same pass draws offscreen or into a window.

pub mod compare;
pub mod display;
pub mod forward;
/// The frame as a graph: the glue to luz-graph and the building blocks of every frame.
pub mod frame;
/// Frustum planes, bounding spheres and culling, shared by the forward and shadow passes.
pub mod frustum;
pub mod gpu;
pub mod ibl;
pub mod material;
pub mod mesh;
pub mod saturate;
pub mod shadow;
pub mod target;
pub mod tonemap;
