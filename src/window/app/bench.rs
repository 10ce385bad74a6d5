//! The end of a session: the last screenshot, the `--bench` report (frame-time statistics, CSV,
//! JSON) and validation's counts.

use super::*;

impl Viewer {
    /// Ends the session: the final screenshot, the benchmark report, validation's verdict.
    pub(super) fn finish(mut self, args: &ViewOptions) -> Result<ViewOutcome> {
        // SAFETY: the device is live and only this thread submits to its queue, so waiting for idle needs no
        // further synchronisation.
        unsafe { self.ctx.device.device_wait_idle()? };
        if let Some(path) = &args.screenshot {
            // One more frame, copied: what the window shows at the end.
            self.pending_screenshot = Some(path.clone());
            self.frame_limit = None;
            self.frame()?;
            // SAFETY: as above: the extra frame is finished before its screenshot is read.
            unsafe { self.ctx.device.device_wait_idle()? };
        }
        if self.bench {
            self.report_bench(args)?;
        }
        let stats = self.profiler.stats();
        log::info!(
            "frames: {} shown, frame time p50 {:.2} ms, p95 {:.2} ms, p99 {:.2} ms, {} stutters (> 2x median)",
            self.frame_index, stats.p50, stats.p95, stats.p99, stats.stutters
        );
        if let Some(line) = self.lab.summary() {
            log::info!("{line}");
        }
        let ctx = self.ctx.clone();
        drop(self);
        let log = ctx.validation_log();
        Ok(ViewOutcome {
            validation: ctx.instance.validation,
            validation_errors: log.errors(),
            validation_warnings: log.warnings(),
        })
    }

    pub(super) fn report_bench(&self, args: &ViewOptions) -> Result<()> {
        let frames: Vec<&FrameSample> = self
            .bench_frames
            .iter()
            .skip(self.warmup as usize)
            .collect();
        if frames.is_empty() {
            return Err(anyhow!(
                "--bench: no frames after the {} warm-up frames; raise --frames",
                self.warmup
            ));
        }
        let lods: Vec<&lod::FrameLod> = self.bench_lod.iter().skip(self.warmup as usize).collect();
        let budgets: Vec<f64> = lods.iter().map(|l| l.budget as f64).collect();
        let triangles: Vec<f64> = lods.iter().map(|l| l.triangles as f64).collect();
        let adaptive = lods.iter().filter(|l| l.adaptive).count();
        let budget = crate::stats::Summary::of(&budgets);
        let drawn = crate::stats::Summary::of(&triangles);
        let frame_ms: Vec<f64> = frames.iter().map(|f| f.frame_ms).collect();
        let cpu_ms: Vec<f64> = frames.iter().map(|f| f.cpu_ms).collect();
        let summary = crate::stats::Summary::of(&frame_ms);
        let stutters = crate::profiler::stutter_count(&frame_ms);
        let extent = self.swapchain.extent;
        log::info!(
            "view --bench: {} frames at {}x{} ({} triangles, present mode {:?})",
            frames.len(),
            extent.width,
            extent.height,
            self.forward.triangle_count(),
            self.swapchain.present_mode
        );
        log::info!(
            "frame ms (wall, presenting): median {:.2}, p95 {:.2}, p99 {:.2}, max {:.2}; p99/p50 {:.3}; stutters {}",
            summary.median,
            summary.p95,
            summary.p99,
            summary.max,
            summary.p99 / summary.median,
            stutters
        );
        log::info!(
            "LOD budget px: median {:.3}, min {:.3}, max {:.3} ({} of {} frames adaptive; {}; \
             scene {} px); triangles drawn: median {:.0}, min {:.0}, max {:.0}",
            budget.median,
            budget.min,
            budget.max,
            adaptive,
            lods.len(),
            match self.lod_target.target_ms() {
                Some(t) => format!("target {t} ms"),
                None => "no target".to_string(),
            },
            self.lod_target.scene_budget(),
            drawn.median,
            drawn.min,
            drawn.max
        );
        let mut names: Vec<&'static str> = Vec::new();
        for f in &frames {
            for (n, _) in &f.gpu_ms {
                if !names.contains(n) {
                    names.push(n);
                }
            }
        }
        let mut passes = serde_json::Map::new();
        for n in &names {
            let v: Vec<f64> = frames
                .iter()
                .filter_map(|f| f.gpu_ms.iter().find(|(m, _)| m == n).map(|(_, t)| *t))
                .collect();
            let s = crate::stats::Summary::of(&v);
            log::info!(
                "  GPU {n:<20} median {:8.3} ms  p95 {:8.3}  p99 {:8.3}",
                s.median,
                s.p95,
                s.p99
            );
            passes.insert(n.to_string(), serde_json::to_value(s)?);
        }
        if let Some(p) = &args.files.csv {
            let mut out = String::from("frame,frame_ms,cpu_ms,lod_budget_px,triangles_drawn");
            for n in &names {
                out.push_str(&format!(",gpu_{n}_ms"));
            }
            out.push('\n');
            for (i, f) in frames.iter().enumerate() {
                let l = lods.get(i).copied().copied().unwrap_or_default();
                out.push_str(&format!(
                    "{i},{:.4},{:.4},{},{}",
                    f.frame_ms, f.cpu_ms, l.budget, l.triangles
                ));
                for n in &names {
                    let t = f.gpu_ms.iter().find(|(m, _)| m == n).map(|(_, t)| *t);
                    out.push_str(&format!(",{:.4}", t.unwrap_or(f64::NAN)));
                }
                out.push('\n');
            }
            std::fs::write(p, out).with_context(|| format!("cannot write {}", p.display()))?;
            log::info!("wrote {}", p.display());
        }
        if let Some(p) = &args.files.trace {
            // Frames back to back on the CPU track (each its wall time, the recording inside
            // it); a frame's GPU passes start where its recording ends, or where the previous
            // frame's end on the GPU.
            let mut trace = crate::graph::Trace::new();
            let mut t = 0.0;
            for (i, f) in frames.iter().enumerate() {
                let (frame, record) = (f.frame_ms * 1e3, f.cpu_ms.min(f.frame_ms) * 1e3);
                trace.sequential_frame(
                    i as u64,
                    t,
                    ("record + submit", record),
                    ("rest of the frame", frame),
                    &f.gpu_ms,
                );
                t += frame.max(record);
            }
            std::fs::write(p, trace.to_json())
                .with_context(|| format!("cannot write {}", p.display()))?;
            log::info!("wrote {}", p.display());
        }
        if let Some(p) = &args.files.json {
            let json = serde_json::json!({
                "device": self.ctx.info.summary(),
                "mode": "view --bench (windowed, presenting)",
                "present_mode": format!("{:?}", self.swapchain.present_mode),
                "frames": frames.len(),
                "warmup": self.warmup,
                "width": extent.width,
                "height": extent.height,
                "triangles": self.forward.triangle_count(),
                // Of the last frame: after frustum culling, at the LOD levels chosen for the
                // window's height.
                "triangles_drawn": self.forward.triangles_drawn(self.slot),
                // Per measured frame: the mesh LOD budget it drew with (the frame-time target's,
                // or the scene's) and the triangles it drew.
                "lod_target_ms": self.lod_target.target_ms(),
                "scene_lod_budget_px": self.lod_target.scene_budget(),
                "lod_budget_px": budget,
                "adaptive_frames": adaptive,
                "triangles_drawn_per_frame": drawn,
                "turntable_deg_per_frame": self.turntable,
                "frame_ms": summary,
                "p99_over_p50": summary.p99 / summary.median,
                "stutters": stutters,
                "cpu_ms": crate::stats::Summary::of(&cpu_ms),
                "gpu_pass_ms": passes,
            });
            std::fs::write(p, serde_json::to_string_pretty(&json)?)
                .with_context(|| format!("cannot write {}", p.display()))?;
            log::info!("wrote {}", p.display());
        }
        Ok(())
    }
}
