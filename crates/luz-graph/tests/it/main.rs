//! The frame graph's tests: no GPU, execution goes through a logging fake recorder.

mod common;
mod exec;
mod hazards;
mod pool;
mod scene;
mod show;
mod trace;
