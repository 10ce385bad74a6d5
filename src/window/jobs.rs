//! The viewer's background work, off the frame loop: the error view (the CPU reference of the
//! current view with rayon, then the per-pixel error of the GPU image against it). The frame loop
//! only starts jobs and polls for results ([`ReferenceJob::poll`]); it never waits. (The A/B maps
//! are computed on the GPU every frame: `crate::render::compare`.)

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender, TryRecvError};
use std::sync::Arc;
use std::time::Instant;

use crate::color::Tonemap;
use crate::compare::{colorize, flip_map, relative_error_map, ErrorMap, MapStats};
use crate::imageio::LinearImage;
use crate::reference::{render_reference_cancellable, ReferenceOptions};
use crate::scene::Scene;

/// What a comparison map measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapKind {
    /// `max_c |A − B|`, linear radiance.
    Difference,
    /// LDR FLIP of B against A after exposure and tone map.
    Flip,
    /// `max_c |GPU − reference| / reference` (error view).
    Relative,
    /// LDR FLIP of the GPU image against the reference (error view).
    FlipReference,
}

impl MapKind {
    pub fn label(self) -> &'static str {
        match self {
            MapKind::Difference => "|A − B| (linear radiance)",
            MapKind::Flip => "FLIP of B against A",
            MapKind::Relative => "relative error against the reference",
            MapKind::FlipReference => "FLIP against the reference",
        }
    }
}

/// A coloured map ready to show, with its figures.
#[derive(Debug, Clone)]
pub struct MapImage {
    pub kind: MapKind,
    pub width: u32,
    pub height: u32,
    /// RGBA8, row-major.
    pub rgba: Vec<u8>,
    pub stats: MapStats,
    /// The value shown as the top of the colour bar.
    pub scale: f32,
    /// Time to compute the map and colour it, on the worker.
    pub ms: f64,
}

/// The colour-bar top of a map: FLIP and relative error on fixed scales (1 and 25 %) so two
/// views compare; a radiance difference on its 99th percentile (its maximum when that is 0, so
/// identical inputs stay one colour).
fn scale_of(kind: MapKind, stats: &MapStats) -> f32 {
    match kind {
        MapKind::Flip | MapKind::FlipReference => 1.0,
        MapKind::Relative => 0.25,
        MapKind::Difference => {
            if stats.p99 > 0.0 {
                stats.p99
            } else {
                stats.max
            }
        }
    }
}

pub fn map_image(kind: MapKind, map: ErrorMap, started: Instant) -> MapImage {
    let stats = MapStats::of(&map.values);
    let scale = scale_of(kind, &stats);
    MapImage {
        kind,
        width: map.width,
        height: map.height,
        rgba: colorize(&map, scale),
        stats,
        scale,
        ms: started.elapsed().as_secs_f64() * 1e3,
    }
}

/// What the error view shows once the reference is done.
#[derive(Debug, Clone)]
pub struct ErrorResult {
    pub relative: MapImage,
    pub flip: MapImage,
    /// Time the reference took (rayon, every core), and its size.
    pub reference_ms: f64,
    pub width: u32,
    pub height: u32,
}

/// The CPU reference of one view, rendering on its own thread (rayon inside); the GPU image of
/// the same view arrives later through [`ReferenceJob::give_gpu_image`].
pub struct ReferenceJob {
    cancel: Arc<AtomicBool>,
    rows: Arc<AtomicU64>,
    pub total_rows: u64,
    gpu: Option<Sender<LinearImage>>,
    result: Receiver<Result<Option<ErrorResult>, String>>,
}

impl ReferenceJob {
    /// Starts rendering `scene` (its camera and output size are the view's).
    pub fn start(scene: Scene, opts: ReferenceOptions, exposure: f32, tonemap: Tonemap) -> Self {
        let cancel = Arc::new(AtomicBool::new(false));
        let rows = Arc::new(AtomicU64::new(0));
        let (gpu_tx, gpu_rx) = channel::<LinearImage>();
        let (tx, result) = channel();
        let total_rows = u64::from(scene.output.height);
        let (c, r) = (cancel.clone(), rows.clone());
        let spawned = std::thread::Builder::new()
            .name("luz-reference".into())
            .spawn(move || {
                let started = Instant::now();
                let out = match render_reference_cancellable(&scene, &opts, &r, &c) {
                    Err(e) => Err(format!("{e:#}")),
                    Ok(None) => Ok(None),
                    Ok(Some(reference)) => {
                        let reference_ms = started.elapsed().as_secs_f64() * 1e3;
                        match gpu_rx.recv() {
                            Err(_) => Ok(None),
                            Ok(gpu) if c.load(Ordering::Relaxed) => {
                                drop(gpu);
                                Ok(None)
                            }
                            Ok(gpu) => Ok(Some(error_result(
                                &gpu,
                                &reference,
                                exposure,
                                tonemap,
                                reference_ms,
                            ))),
                        }
                    }
                };
                let _ = tx.send(out);
            });
        if let Err(e) = spawned {
            let (tx, rx) = channel();
            let _ = tx.send(Err(format!("cannot start the reference thread: {e}")));
            return Self {
                cancel,
                rows,
                total_rows,
                gpu: None,
                result: rx,
            };
        }
        Self {
            cancel,
            rows,
            total_rows,
            gpu: Some(gpu_tx),
            result,
        }
    }

    /// The GPU's image of the same view (read back after the frame that started the job).
    pub fn give_gpu_image(&mut self, image: LinearImage) {
        if let Some(tx) = self.gpu.take() {
            let _ = tx.send(image);
        }
    }

    pub fn wants_gpu_image(&self) -> bool {
        self.gpu.is_some()
    }

    /// Rows of the reference done so far.
    pub fn rows_done(&self) -> u64 {
        self.rows.load(Ordering::Relaxed)
    }

    /// `None` while running; then the result (`Ok(None)`: cancelled).
    pub fn poll(&mut self) -> Option<Result<Option<ErrorResult>, String>> {
        match self.result.try_recv() {
            Ok(r) => Some(r),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => Some(Err("the reference thread stopped".into())),
        }
    }
}

impl Drop for ReferenceJob {
    /// Cancels: the thread skips its remaining rows and ends on its own (it is not joined, so
    /// the frame loop never waits for it).
    fn drop(&mut self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
}

fn error_result(
    gpu: &LinearImage,
    reference: &LinearImage,
    exposure: f32,
    tonemap: Tonemap,
    reference_ms: f64,
) -> ErrorResult {
    let (w, h) = (reference.width, reference.height);
    let started = Instant::now();
    let relative = if (gpu.width, gpu.height) == (w, h) {
        relative_error_map(&gpu.pixels, &reference.pixels, w, h)
    } else {
        // Cannot happen (both come from the same view); an all-infinite map shows it if it does.
        ErrorMap {
            width: w,
            height: h,
            values: vec![f32::INFINITY; reference.pixels.len()],
        }
    };
    let relative = map_image(MapKind::Relative, relative, started);
    let started = Instant::now();
    let flip = if (gpu.width, gpu.height) == (w, h) {
        flip_map(&reference.pixels, &gpu.pixels, (w, h), (exposure, tonemap))
    } else {
        ErrorMap {
            width: w,
            height: h,
            values: vec![1.0; reference.pixels.len()],
        }
    };
    let flip = map_image(MapKind::FlipReference, flip, started);
    ErrorResult {
        relative,
        flip,
        reference_ms,
        width: w,
        height: h,
    }
}
