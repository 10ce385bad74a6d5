//! The named kinds of use a pass declares for a resource, each one row of a table mapping it to
//! the image layout, pipeline stages and access flags (synchronization2) that use needs.

use ash::vk;
use vk::AccessFlags2 as A;
use vk::ImageLayout as L;
use vk::PipelineStageFlags2 as S;

/// A global memory barrier: a source and a destination scope, as every barrier has them (the
/// `scopes` of [`crate::ImageBarrier`], [`crate::BufferBarrier`] and [`crate::BarrierInfo`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MemoryBarrier {
    /// Source stages.
    pub src_stages: vk::PipelineStageFlags2,
    /// Source accesses.
    pub src_access: vk::AccessFlags2,
    /// Destination stages.
    pub dst_stages: vk::PipelineStageFlags2,
    /// Destination accesses.
    pub dst_access: vk::AccessFlags2,
}

/// Which resources an [`Access`] applies to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AppliesTo {
    /// Images only (the layout matters).
    Image,
    /// Buffers only (the layout is ignored).
    Buffer,
    /// Both images and buffers.
    Both,
}

/// One row of the access table: everything the barrier derivation needs to know about a use.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct AccessInfo {
    /// The name shown in DOT/SVG output.
    pub name: &'static str,
    /// The image layout the use needs (ignored for buffers).
    pub layout: vk::ImageLayout,
    /// The pipeline stages that perform the use.
    pub stages: vk::PipelineStageFlags2,
    /// The memory accesses the use performs.
    pub access: vk::AccessFlags2,
    /// Whether the use writes the resource.
    pub writes: bool,
    /// Which resources the use applies to.
    pub applies_to: AppliesTo,
}

/// Every access flag that is a write; the source access of a barrier only ever needs these
/// (reads need no availability operation, only an execution dependency).
pub const WRITE_ACCESS: vk::AccessFlags2 = A::from_raw(
    A::SHADER_WRITE.as_raw()
        | A::SHADER_STORAGE_WRITE.as_raw()
        | A::COLOR_ATTACHMENT_WRITE.as_raw()
        | A::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw()
        | A::TRANSFER_WRITE.as_raw()
        | A::HOST_WRITE.as_raw()
        | A::MEMORY_WRITE.as_raw(),
);

/// A named kind of use of an image or a buffer by a pass.
///
/// `DepthAttachmentRead` uses `DEPTH_READ_ONLY_OPTIMAL` (a read-only depth test): it needs a layout
/// transition after a depth write, and lets the same image be sampled as a depth texture in the
/// same layout. Sampling a depth image (shadow maps) uses the `*Sampled` kinds
/// (`SHADER_READ_ONLY_OPTIMAL`, valid for depth formats), as luz's descriptors do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Access {
    /// Colour attachment, cleared or fully overwritten (`loadOp` CLEAR/DONT_CARE).
    ColorAttachmentWrite,
    /// Colour attachment loaded and stored (`loadOp` LOAD, blending).
    ColorAttachmentReadWrite,
    /// Depth attachment with depth writes (tests read it too).
    DepthAttachmentWrite,
    /// Depth attachment tested without writes, in `DEPTH_READ_ONLY_OPTIMAL`.
    DepthAttachmentRead,
    /// Sampled in a vertex shader.
    VertexSampled,
    /// Sampled in a fragment shader.
    FragmentSampled,
    /// Sampled in a compute shader.
    ComputeSampled,
    /// Storage image read in a fragment shader (`GENERAL`).
    FragmentStorageRead,
    /// Storage image read in a compute shader (`GENERAL`).
    ComputeStorageRead,
    /// Storage image written by a compute shader (`GENERAL`).
    ComputeStorageWrite,
    /// Storage image read and written by a compute shader (`GENERAL`).
    ComputeStorageReadWrite,
    /// Source of a copy or blit (images: `TRANSFER_SRC_OPTIMAL`; buffers too).
    TransferSrc,
    /// Destination of a copy, blit or clear (images: `TRANSFER_DST_OPTIMAL`; buffers too).
    TransferDst,
    /// Handed to the presentation engine (`PRESENT_SRC_KHR`, no stages, no accesses: the
    /// semaphore signalled by the submission orders it).
    Present,
    /// Read by the host after the submission's fence (buffers).
    HostRead,
    /// Uniform buffer read by vertex, fragment or compute shaders.
    UniformRead,
    /// Vertex buffer read by the input assembler.
    VertexRead,
    /// Index buffer read by the input assembler.
    IndexRead,
    /// Indirect draw/dispatch arguments.
    IndirectRead,
    /// Storage buffer read by a compute shader.
    ComputeStorageBufferRead,
    /// Storage buffer written by a compute shader.
    ComputeStorageBufferWrite,
    /// Storage buffer read and written by a compute shader.
    ComputeStorageBufferReadWrite,
    /// Storage buffer read by a fragment shader.
    FragmentStorageBufferRead,
    /// Storage buffer written by a fragment shader.
    FragmentStorageBufferWrite,
    /// Anything else, spelled out.
    Custom {
        /// Its name in the graph's pictures.
        name: &'static str,
        /// The image layout (ignored for buffers).
        layout: vk::ImageLayout,
        /// The stages of the use.
        stages: vk::PipelineStageFlags2,
        /// The accesses of the use.
        access: vk::AccessFlags2,
        /// Whether it writes.
        writes: bool,
    },
}

const FRAG_TESTS: S =
    S::from_raw(S::EARLY_FRAGMENT_TESTS.as_raw() | S::LATE_FRAGMENT_TESTS.as_raw());
/// Colour attachment loaded and stored.
const COLOR_READ_WRITE: A =
    A::from_raw(A::COLOR_ATTACHMENT_READ.as_raw() | A::COLOR_ATTACHMENT_WRITE.as_raw());
/// Depth test and depth write.
const DEPTH_READ_WRITE: A = A::from_raw(
    A::DEPTH_STENCIL_ATTACHMENT_READ.as_raw() | A::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
);
/// Storage image or buffer read and written.
const STORAGE_READ_WRITE: A =
    A::from_raw(A::SHADER_STORAGE_READ.as_raw() | A::SHADER_STORAGE_WRITE.as_raw());

/// Builds one row of the table.
const fn row(
    name: &'static str,
    layout: L,
    stages: S,
    access: A,
    writes: bool,
    applies_to: AppliesTo,
) -> AccessInfo {
    AccessInfo {
        name,
        layout,
        stages,
        access,
        writes,
        applies_to,
    }
}

impl Access {
    /// Every named kind (without `Custom`), in table order.
    pub const ALL: [Access; 24] = [
        Access::ColorAttachmentWrite,
        Access::ColorAttachmentReadWrite,
        Access::DepthAttachmentWrite,
        Access::DepthAttachmentRead,
        Access::VertexSampled,
        Access::FragmentSampled,
        Access::ComputeSampled,
        Access::FragmentStorageRead,
        Access::ComputeStorageRead,
        Access::ComputeStorageWrite,
        Access::ComputeStorageReadWrite,
        Access::TransferSrc,
        Access::TransferDst,
        Access::Present,
        Access::HostRead,
        Access::UniformRead,
        Access::VertexRead,
        Access::IndexRead,
        Access::IndirectRead,
        Access::ComputeStorageBufferRead,
        Access::ComputeStorageBufferWrite,
        Access::ComputeStorageBufferReadWrite,
        Access::FragmentStorageBufferRead,
        Access::FragmentStorageBufferWrite,
    ];

    /// The table row of this kind.
    pub const fn info(self) -> AccessInfo {
        use AppliesTo::{Both, Buffer, Image};
        match self {
            Access::ColorAttachmentWrite => row(
                "ColorAttachmentWrite",
                L::COLOR_ATTACHMENT_OPTIMAL,
                S::COLOR_ATTACHMENT_OUTPUT,
                A::COLOR_ATTACHMENT_WRITE,
                true,
                Image,
            ),
            Access::ColorAttachmentReadWrite => row(
                "ColorAttachmentReadWrite",
                L::COLOR_ATTACHMENT_OPTIMAL,
                S::COLOR_ATTACHMENT_OUTPUT,
                COLOR_READ_WRITE,
                true,
                Image,
            ),
            Access::DepthAttachmentWrite => row(
                "DepthAttachmentWrite",
                L::DEPTH_ATTACHMENT_OPTIMAL,
                FRAG_TESTS,
                DEPTH_READ_WRITE,
                true,
                Image,
            ),
            Access::DepthAttachmentRead => row(
                "DepthAttachmentRead",
                L::DEPTH_READ_ONLY_OPTIMAL,
                FRAG_TESTS,
                A::DEPTH_STENCIL_ATTACHMENT_READ,
                false,
                Image,
            ),
            Access::VertexSampled => row(
                "VertexSampled",
                L::SHADER_READ_ONLY_OPTIMAL,
                S::VERTEX_SHADER,
                A::SHADER_SAMPLED_READ,
                false,
                Image,
            ),
            Access::FragmentSampled => row(
                "FragmentSampled",
                L::SHADER_READ_ONLY_OPTIMAL,
                S::FRAGMENT_SHADER,
                A::SHADER_SAMPLED_READ,
                false,
                Image,
            ),
            Access::ComputeSampled => row(
                "ComputeSampled",
                L::SHADER_READ_ONLY_OPTIMAL,
                S::COMPUTE_SHADER,
                A::SHADER_SAMPLED_READ,
                false,
                Image,
            ),
            Access::FragmentStorageRead => row(
                "FragmentStorageRead",
                L::GENERAL,
                S::FRAGMENT_SHADER,
                A::SHADER_STORAGE_READ,
                false,
                Image,
            ),
            Access::ComputeStorageRead => row(
                "ComputeStorageRead",
                L::GENERAL,
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ,
                false,
                Image,
            ),
            Access::ComputeStorageWrite => row(
                "ComputeStorageWrite",
                L::GENERAL,
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_WRITE,
                true,
                Image,
            ),
            Access::ComputeStorageReadWrite => row(
                "ComputeStorageReadWrite",
                L::GENERAL,
                S::COMPUTE_SHADER,
                STORAGE_READ_WRITE,
                true,
                Image,
            ),
            Access::TransferSrc => row(
                "TransferSrc",
                L::TRANSFER_SRC_OPTIMAL,
                S::COPY,
                A::TRANSFER_READ,
                false,
                Both,
            ),
            Access::TransferDst => row(
                "TransferDst",
                L::TRANSFER_DST_OPTIMAL,
                S::COPY,
                A::TRANSFER_WRITE,
                true,
                Both,
            ),
            Access::Present => row(
                "Present",
                L::PRESENT_SRC_KHR,
                S::NONE,
                A::NONE,
                false,
                Image,
            ),
            Access::HostRead => row("HostRead", L::GENERAL, S::HOST, A::HOST_READ, false, Buffer),
            Access::UniformRead => row(
                "UniformRead",
                L::UNDEFINED,
                S::from_raw(
                    S::VERTEX_SHADER.as_raw()
                        | S::FRAGMENT_SHADER.as_raw()
                        | S::COMPUTE_SHADER.as_raw(),
                ),
                A::UNIFORM_READ,
                false,
                Buffer,
            ),
            Access::VertexRead => row(
                "VertexRead",
                L::UNDEFINED,
                S::VERTEX_ATTRIBUTE_INPUT,
                A::VERTEX_ATTRIBUTE_READ,
                false,
                Buffer,
            ),
            Access::IndexRead => row(
                "IndexRead",
                L::UNDEFINED,
                S::INDEX_INPUT,
                A::INDEX_READ,
                false,
                Buffer,
            ),
            Access::IndirectRead => row(
                "IndirectRead",
                L::UNDEFINED,
                S::DRAW_INDIRECT,
                A::INDIRECT_COMMAND_READ,
                false,
                Buffer,
            ),
            Access::ComputeStorageBufferRead => row(
                "ComputeStorageBufferRead",
                L::UNDEFINED,
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ,
                false,
                Buffer,
            ),
            Access::ComputeStorageBufferWrite => row(
                "ComputeStorageBufferWrite",
                L::UNDEFINED,
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_WRITE,
                true,
                Buffer,
            ),
            Access::ComputeStorageBufferReadWrite => row(
                "ComputeStorageBufferReadWrite",
                L::UNDEFINED,
                S::COMPUTE_SHADER,
                STORAGE_READ_WRITE,
                true,
                Buffer,
            ),
            Access::FragmentStorageBufferRead => row(
                "FragmentStorageBufferRead",
                L::UNDEFINED,
                S::FRAGMENT_SHADER,
                A::SHADER_STORAGE_READ,
                false,
                Buffer,
            ),
            Access::FragmentStorageBufferWrite => row(
                "FragmentStorageBufferWrite",
                L::UNDEFINED,
                S::FRAGMENT_SHADER,
                A::SHADER_STORAGE_WRITE,
                true,
                Buffer,
            ),
            Access::Custom {
                name,
                layout,
                stages,
                access,
                writes,
            } => row(name, layout, stages, access, writes, Both),
        }
    }

    /// The name of this kind (DOT/SVG labels).
    pub const fn name(self) -> &'static str {
        self.info().name
    }

    /// The image layout of this kind (meaningless for buffers).
    pub const fn layout(self) -> vk::ImageLayout {
        self.info().layout
    }

    /// The pipeline stages of this kind.
    pub const fn stages(self) -> vk::PipelineStageFlags2 {
        self.info().stages
    }

    /// The access flags of this kind.
    pub const fn access(self) -> vk::AccessFlags2 {
        self.info().access
    }

    /// Whether this kind writes the resource.
    pub const fn writes(self) -> bool {
        self.info().writes
    }

    /// The image usage flags an image needs for this kind of use (empty for buffer kinds and
    /// `Custom`).
    pub const fn image_usage(self) -> vk::ImageUsageFlags {
        use vk::ImageUsageFlags as U;
        match self {
            Access::ColorAttachmentWrite | Access::ColorAttachmentReadWrite => U::COLOR_ATTACHMENT,
            Access::DepthAttachmentWrite | Access::DepthAttachmentRead => {
                U::DEPTH_STENCIL_ATTACHMENT
            }
            Access::VertexSampled | Access::FragmentSampled | Access::ComputeSampled => U::SAMPLED,
            Access::FragmentStorageRead
            | Access::ComputeStorageRead
            | Access::ComputeStorageWrite
            | Access::ComputeStorageReadWrite => U::STORAGE,
            Access::TransferSrc => U::TRANSFER_SRC,
            Access::TransferDst => U::TRANSFER_DST,
            _ => U::empty(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_is_consistent() {
        for a in Access::ALL {
            let i = a.info();
            // A kind writes exactly when its access flags contain a write.
            assert_eq!(i.writes, i.access.intersects(WRITE_ACCESS), "{}", i.name);
            assert_eq!(format!("{a:?}"), i.name);
        }
    }
}
