//! Fakes: images, a factory, a logging recorder and timer sharing one log.

use std::cell::RefCell;
use std::fmt;
use std::rc::Rc;

use ash::vk;
use ash::vk::Handle;
use luz_graph::*;

pub type Log = Rc<RefCell<Vec<String>>>;

pub fn log() -> Log {
    Rc::new(RefCell::new(Vec::new()))
}

#[derive(Debug)]
pub struct FakeImage {
    pub id: u64,
}

impl PooledImage for FakeImage {
    fn raw(&self) -> vk::Image {
        vk::Image::from_raw(self.id)
    }
    fn view(&self) -> vk::ImageView {
        vk::ImageView::from_raw(self.id + 1000)
    }
}

#[derive(Debug)]
pub struct FakeError;

impl fmt::Display for FakeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("fake allocation failure")
    }
}

impl std::error::Error for FakeError {}

#[derive(Default)]
pub struct FakeFactory {
    pub next: u64,
    pub created: Vec<(String, ImageDesc)>,
}

impl ImageFactory for FakeFactory {
    type Image = FakeImage;
    type Error = FakeError;
    fn create(&mut self, name: &str, desc: &ImageDesc) -> Result<FakeImage, FakeError> {
        self.next += 1;
        self.created.push((name.to_string(), *desc));
        Ok(FakeImage { id: self.next })
    }
}

pub struct FakeRecorder {
    device: ash::Device,
    pub batches: Vec<BarrierBatch>,
    pub log: Log,
}

impl FakeRecorder {
    pub fn new(log: &Log) -> Self {
        // SAFETY: a loader returning null for every function makes ash install stubs that panic
        // when called; no test calls a device function (the fake records barriers itself).
        let device = unsafe { ash::Device::load_with(|_| std::ptr::null(), vk::Device::null()) };
        Self {
            device,
            batches: Vec::new(),
            log: log.clone(),
        }
    }
}

impl Recorder for FakeRecorder {
    fn device(&self) -> &ash::Device {
        &self.device
    }
    fn pipeline_barrier(&mut self, _cmd: vk::CommandBuffer, batch: &BarrierBatch) {
        self.log.borrow_mut().push(format!(
            "barrier {}i {}b {}m",
            batch.images.len(),
            batch.buffers.len(),
            batch.memory.len()
        ));
        self.batches.push(batch.clone());
    }
}

pub struct FakeTimer {
    pub log: Log,
    pub next: u32,
}

impl PassTimer for FakeTimer {
    fn begin(&mut self, _cmd: vk::CommandBuffer, name: &'static str) -> Option<u32> {
        self.log.borrow_mut().push(format!("begin {name}"));
        self.next += 1;
        Some(self.next - 1)
    }
    fn end(&mut self, _cmd: vk::CommandBuffer, slot: Option<u32>) {
        self.log.borrow_mut().push(format!("end {slot:?}"));
    }
}

/// A null command buffer: the fake recorder never uses it.
pub fn cmd() -> vk::CommandBuffer {
    vk::CommandBuffer::null()
}

pub fn color(w: u32) -> ImageDesc {
    ImageDesc::color(w, w, vk::Format::R16G16B16A16_SFLOAT)
}

pub fn imported(id: u64, desc: ImageDesc) -> ImportedImage {
    ImportedImage::new(
        vk::Image::from_raw(id),
        vk::ImageView::from_raw(id + 1000),
        desc,
    )
}

/// Executes `g` against the fakes; returns the report and the recorder.
pub fn run(
    g: FrameGraph<'_>,
    pool: &mut TransientPool<FakeFactory>,
    factory: &mut FakeFactory,
    log: &Log,
) -> (Result<ExecReport, GraphError>, FakeRecorder) {
    let mut rec = FakeRecorder::new(log);
    let compiled = g.compile().expect("compiles");
    let r = compiled.execute_with(&mut rec, cmd(), pool, factory, None);
    (r, rec)
}

/// The one image barrier of `batch` on `image`.
pub fn image_barrier(batch: &BarrierBatch, image: vk::Image) -> ImageBarrier {
    let found: Vec<_> = batch.images.iter().filter(|b| b.image == image).collect();
    assert_eq!(found.len(), 1, "{batch:?}");
    *found[0]
}
