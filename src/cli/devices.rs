//! `luz devices`: the Vulkan devices luz can use and the one it would pick.

use std::process::ExitCode;

use anyhow::Result;

use super::common::{context, validation_exit, GpuArgs};

pub fn run(a: GpuArgs) -> Result<ExitCode> {
    let ctx = context(&a)?;
    println!("{}", ctx.info.summary());
    println!(
        "  maxImageDimension2D {}, maxPushConstantsSize {}, minUniformBufferOffsetAlignment {}, \
         timestampPeriod {} ns, timestampValidBits {}",
        ctx.info.limits.max_image_dimension2_d,
        ctx.info.limits.max_push_constants_size,
        ctx.info.limits.min_uniform_buffer_offset_alignment,
        ctx.info.timestamp_period_ns,
        ctx.info.timestamp_valid_bits
    );
    Ok(validation_exit(&ctx))
}
