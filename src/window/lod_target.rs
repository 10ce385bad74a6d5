//! The viewer's frame-time target (`luz view --target-ms`): while the view changes, the mesh LOD
//! budget (px) rises above the scene's `output.tessellation_error_px` when frames exceed the target
//! and falls back when they are faster, never below the scene's; once the view has been still for
//! [`REST_FRAMES`] frames the viewer draws at the scene's budget (the exact picture, the one `luz
//! render` makes) until something changes.
//!
//! The controller works on the log of the budget. A frame's cost on lavapipe follows the triangles
//! drawn, and those fall as a power of the budget (≈ budget^-0.85 on the bunny rows), so `ln(ms)`
//! is close to linear in `ln(budget)`. Each measured frame (drawn at budget `u`, taking `t` ms
//! against the target `T`) gives an estimate of the log budget that meets the target, `ln u + ln(t
//! / T) / ELASTICITY`; the budget moves half way towards it ([`GAIN`]), by at most a factor of 2
//! per frame. The estimate is anchored on the budget the *measured* frame was drawn with, not the
//! current one, so the two frames of latency between drawing and reading the timestamps do not
//! compound into overshoot: with a true elasticity `e`, the error shrinks by at least `(1 - GAIN) +
//! GAIN · |1 - e / ELASTICITY|` per frame, which is below 1 for any `0 < e < 2 · ELASTICITY`. Two
//! hystereses keep it from hunting: frames from 8 % over the target to 30 % under it leave the
//! budget alone (noise; [`BAND_OVER`], [`BAND_UNDER`]), and for [`HOLD_FRAMES`] measured frames
//! after a frame was too slow the budget is not lowered back to the one that frame was drawn with
//! (a change of LOD level that moves the frame time across the whole band, as one large mesh's can,
//! would otherwise flip it between two levels every few frames).
//!
//! Pure logic, no window: the viewer feeds it ([`LodTarget::frame`], [`LodTarget::observe`]) and
//! hands the budget to the headless core (`ForwardPass::set_lod_budget`).

/// Still frames after which the viewer draws at the scene's budget.
pub const REST_FRAMES: u32 = 3;
/// The adaptive budget's ceiling (px; a scene's own larger budget raises it): coarser levels
/// show, and on the 40 M bunny scene the frame time hardly falls beyond it (2.2 → 7.9 px drew
/// 470 k → 270 k triangles for about the same 100 ms: the frame's fixed costs dominate). A target
/// that cannot be met below it leaves the budget there.
pub const MAX_BUDGET_PX: f32 = 4.0;
/// The adaptive budget's floor when the scene asks for full detail (budget 0): at the floor the
/// viewer draws at the scene's budget itself.
pub const FLOOR_PX: f32 = 0.05;
/// The assumed elasticity of frame time with respect to the budget, `-d ln(ms) / d ln(budget)`
/// (the exponent of triangles drawn; fixed costs make the true one smaller, which only slows
/// convergence).
pub const ELASTICITY: f64 = 0.85;
/// Share of the way to the estimate the budget moves per measured frame.
pub const GAIN: f64 = 0.5;
/// Frames from 8 % over the target ([`BAND_OVER`]) to 30 % under it (`1 / 1.3`, [`BAND_UNDER`])
/// leave the budget alone: asymmetric, so that it settles under the target rather than over.
pub const BAND_OVER: f64 = 0.08;
pub const BAND_UNDER: f64 = 0.3;
/// The largest change of the log budget per frame (a factor of 2).
const MAX_STEP: f64 = std::f64::consts::LN_2;
/// Measured frames for which a budget found too slow bounds the lowering of the budget; each time
/// the same budget (within 25 %) is found too slow again the hold doubles, up to
/// [`MAX_HOLD_FRAMES`].
pub const HOLD_FRAMES: u32 = 20;
pub const MAX_HOLD_FRAMES: u32 = 320;
/// Budgets within 25 % count as the same one for the hold.
const SAME_BUDGET: f64 = 0.223;
/// How far above a budget found too slow lowering stops (5 %).
const RATCHET_MARGIN: f64 = 0.05;

/// The target's default on lavapipe (`--target-ms`): 10 frames per second.
pub const DEFAULT_TARGET_MS: f64 = 100.0;

/// What the budget of the frame being drawn follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// No target (`--target-ms 0|off`), or nothing it could act on: the scene's budget.
    Off,
    /// The view is changing: the adaptive budget.
    Adaptive,
    /// The view has been still for [`REST_FRAMES`] frames: the scene's budget.
    Rest,
}

/// The frame-time controller of the mesh LOD budget (see the module's documentation).
#[derive(Debug, Clone)]
pub struct LodTarget {
    target_ms: Option<f64>,
    scene_budget: f32,
    /// ln(px) of the adaptive budget, in `[floor, ceiling]`; kept while the view rests, so that
    /// motion resumes at the budget that met the target.
    log_budget: f64,
    /// A frame drawn at the adaptive budget has been measured: from then on frames drawn at the
    /// scene's budget (at rest) no longer move it.
    learned: bool,
    /// The last budget measured too slow: lowering stops above it for a while.
    slow: Option<Slow>,
    /// The adaptive budget has left its floor: a scene asking for full detail (0) then draws at
    /// [`FLOOR_PX`], not 0, at the floor while moving (0 was measured too slow).
    raised: bool,
    /// Frames since the view last changed.
    still: u32,
    mode: Mode,
}

impl LodTarget {
    /// A controller holding `target_ms` (`None`, 0 or not finite: off) for a scene whose budget
    /// is `scene_budget` px (0: full detail). The first frames count as a change.
    pub fn new(target_ms: Option<f64>, scene_budget: f32) -> Self {
        let mut t = Self {
            target_ms: target_ms.filter(|t| t.is_finite() && *t > 0.0),
            scene_budget,
            log_budget: 0.0,
            learned: false,
            slow: None,
            raised: false,
            still: 0,
            mode: Mode::Off,
        };
        t.log_budget = t.floor();
        t
    }

    /// The target in ms, if any.
    pub fn target_ms(&self) -> Option<f64> {
        self.target_ms
    }

    /// The scene's budget (px).
    pub fn scene_budget(&self) -> f32 {
        self.scene_budget
    }

    /// The scene's budget changed (an edit, another scene opened): the adaptive budget stays
    /// within the new bounds.
    pub fn set_scene_budget(&mut self, budget: f32) {
        if budget != self.scene_budget {
            self.scene_budget = budget;
            self.raised = false;
            self.slow = None;
            self.log_budget = self.log_budget.clamp(self.floor(), self.ceiling());
        }
    }

    fn floor(&self) -> f64 {
        (self.scene_budget.max(FLOOR_PX) as f64).ln()
    }

    fn ceiling(&self) -> f64 {
        (self.scene_budget.max(MAX_BUDGET_PX) as f64).ln()
    }

    /// Starts a frame: `changed` says whether the view (camera, window, scene) changed since the
    /// last one, `enabled` whether the target may act (the scene has simplified meshes, the lab
    /// compares nothing). Returns the budget (px) to draw the frame with.
    pub fn frame(&mut self, changed: bool, enabled: bool) -> f32 {
        self.still = if changed {
            0
        } else {
            self.still.saturating_add(1)
        };
        self.mode = match (self.target_ms, enabled) {
            (Some(_), true) if self.still < REST_FRAMES => Mode::Adaptive,
            (Some(_), true) => Mode::Rest,
            _ => Mode::Off,
        };
        self.budget()
    }

    /// The budget (px) of the frame [`LodTarget::frame`] started: the scene's unless adaptive,
    /// never below it, and the scene's own value while the adaptive one sits at its floor (0
    /// stays 0 until a frame at 0 is measured too slow; then [`FLOOR_PX`] while moving).
    pub fn budget(&self) -> f32 {
        if self.mode != Mode::Adaptive {
            return self.scene_budget;
        }
        if self.log_budget <= self.floor() + 1e-9 {
            return if self.raised {
                self.scene_budget.max(FLOOR_PX)
            } else {
                self.scene_budget
            };
        }
        (self.log_budget.exp() as f32).max(self.scene_budget)
    }

    /// What the budget of the current frame follows.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// The frame started last is at rest: drawn at the scene's budget, the exact picture, after
    /// [`REST_FRAMES`] still frames. Drawing it again would draw the same picture: the viewer may
    /// wait for the next event instead.
    pub fn exact_drawn(&self) -> bool {
        self.mode == Mode::Rest && self.still >= REST_FRAMES
    }

    /// A measured frame: drawn at `used` px (at the adaptive budget when `adaptive`), it took
    /// `ms` (its GPU time). Until the first adaptive frame is measured, frames drawn at the
    /// scene's budget count too, so that the first motion starts near the target; after it they
    /// do not, so that motion resumes at the budget that met it.
    pub fn observe(&mut self, used: f32, adaptive: bool, ms: f64) {
        let Some(target) = self.target_ms else {
            return;
        };
        if !(ms.is_finite() && ms > 0.0 && used.is_finite()) || (self.learned && !adaptive) {
            return;
        }
        self.learned |= adaptive;
        if let Some(s) = &mut self.slow {
            s.age = s.age.saturating_add(1);
        }
        let error = (ms / target).ln();
        if (-(1.0 + BAND_UNDER).ln()..=(1.0 + BAND_OVER).ln()).contains(&error) {
            return;
        }
        let anchor = (used.max(FLOOR_PX) as f64).ln();
        if error < -std::f64::consts::LN_2 {
            // Under half the target: the view got much cheaper, the budget once too slow says
            // nothing about it any more.
            self.slow = None;
        }
        if error > 0.0 {
            // Too slow again, after the hold, at about the same budget: hold twice as long.
            let hold = match self.slow {
                Some(s) if (s.log_budget - anchor).abs() < SAME_BUDGET => {
                    if s.age > s.hold {
                        (s.hold * 2).min(MAX_HOLD_FRAMES)
                    } else {
                        s.hold
                    }
                }
                _ => HOLD_FRAMES,
            };
            self.slow = Some(Slow {
                log_budget: anchor,
                age: 0,
                hold,
            });
        }
        let estimate = anchor + error / ELASTICITY;
        let step = (GAIN * (estimate - self.log_budget)).clamp(-MAX_STEP, MAX_STEP);
        let mut next = (self.log_budget + step).clamp(self.floor(), self.ceiling());
        if let Some(s) = self.slow.filter(|s| s.age <= s.hold && step < 0.0) {
            // Lowering: not back to a budget measured too slow within its hold (a jump of the
            // frame time across the whole band between two LOD levels would otherwise make the
            // budget hunt between them), and never up.
            next = next.max((s.log_budget + RATCHET_MARGIN).min(self.log_budget));
        }
        self.raised |= next > self.floor() + 1e-9;
        self.log_budget = next;
    }

    /// The profiler's line: the budget in use, why, and the scene's (shown when some mesh has
    /// simplified levels: otherwise [`Mode::Off`] with a target means the lab compares).
    pub fn describe(&self, in_use: f32) -> String {
        let scene = self.scene_budget;
        let scene_text = if scene > 0.0 {
            format!("{scene} px")
        } else {
            "0 = full detail".to_string()
        };
        let used = if in_use > 0.0 {
            format!("{in_use:.2} px")
        } else {
            "0 px (full detail)".to_string()
        };
        match (self.mode, self.target_ms) {
            (_, None) => format!("{used} (scene's; no target)"),
            (Mode::Off, Some(t)) => {
                format!("{used} (scene's; the lab compares, {t} ms target paused)")
            }
            (Mode::Adaptive, Some(t)) => {
                format!("{used} (adaptive, target {t} ms; scene {scene_text})")
            }
            (Mode::Rest, Some(t)) => format!("{used} (scene's, view still; target {t} ms)"),
        }
    }
}

/// A budget measured too slow ([`LodTarget::observe`]).
#[derive(Debug, Clone, Copy)]
struct Slow {
    log_budget: f64,
    /// Frames measured since.
    age: u32,
    /// Frames it bounds the lowering for.
    hold: u32,
}

#[cfg(test)]
mod tests;
