//! The resonant object: shape × material × size → the modes of a [`ModalBank`], heard at two
//! pickups, with a high band that carries the spectrum above the explicit modes.
//!
//! CMJ "Object part" and "Intuitive control" (after Aramaki et al. 2011), docs/MODEL.md §6.
//! For mode k of the chosen [`Shape`], with f₁ = 100 Hz·(1 m / object size):
//!
//! * frequency fₖ = f₁·ratioₖ; explicit modes at or above Nyquist are dropped (no input,
//!   and they ring out if they were sounding);
//! * decay time τₖ = decay·/α(2πfₖ) from the [`Material`] (bounded 0.2 ms … 60 s);
//! * amplitude aₖ = ratioₖ^tilt (the material's spectral balance);
//! * **where the ball is and where it is heard** (docs/MODEL.md §6, "Stereo from mode
//!   shapes"): the force enters mode k with the mode shape at the ball, eₖ = φₖ(ball), and
//!   each channel hears it through the magnitude of the mode shape at its pickup,
//!   pₖ = |φₖ(pickup)| ([`crate::object::shape::PositionShapes`]). The two pickups sit
//!   [`PICKUP_HALF_SPACING`] either side of the listening point along x (reflected at the
//!   edges; a pair placed as mirror images about the centre, listen x = 0, hears a string
//!   or a bar identically, since |sin(kπu)| = |sin(kπ(1 − u))|). Each channel's pickup gains are scaled so that their weighted mean square over
//!   the object's modes is 1 (qₖ = pₖ/B): left and right are equally loud on average and
//!   the ball's position, not the pickups', moves the image. The sign of φ at a pickup is
//!   dropped: two real contact microphones hear some modes in antiphase, which is what
//!   makes a close-miked plate collapse in mono; keeping the magnitude makes L + R never
//!   weaker than either channel.
//! * **width** w: mid mₖ = (qₖᴸ + qₖᴿ)/2, side sₖ = w·(qₖᴸ − qₖᴿ)/2; L = mid + side,
//!   R = mid − side. The bank folds the mid into the input gain and keeps dₖ = sₖ/mₖ
//!   (|dₖ| ≤ w) as the mode's side weight ([`crate::object::bank`]), so L + R is the mono object at
//!   every width.
//! * **level**: the input gain is gₖ = G·aₖ·eₖ·mₖ/(f_s·√E) with E = Σⱼ (aⱼ·eⱼ·mⱼ)²·τⱼ over
//!   every mode below [`HIGH_BAND_TOP_HZ`] (explicit and high band). The 1/f_s makes the
//!   discrete bank approximate the same continuous-time convolution at every sample rate;
//!   the √E keeps the loudness of a broadband (white) force constant whatever the
//!   material, decay, mode count, quality or ball position (a metal object is not 20 dB
//!   louder than a wooden one; it rings longer).
//!
//! ## The high band (docs/MODEL.md §6, "Full band")
//! A real object keeps resonating up the audible band; above its N explicit modes the
//! object here still carries every mode of its series up to min(Nyquist, 24 kHz), through a
//! few representative modes: the band above the last explicit mode is cut into at most
//! [`Quality::high_slots`] groups, equal in log frequency; each group is played by one
//! true mode of the series (its middle one, with its own frequency and decay), whose gains
//! carry the group's energy in the mid and in the side, estimated from up to
//! [`HIGH_SAMPLES`] of the group's modes at the ball and at the pickups. Where the series
//! above the explicit modes has no more modes than slots (a bar, a small object), every
//! one of them is played exactly: sparse shapes keep their partials all the way up. The
//! representatives share the bank (its tail range) and cost what a mode costs.
//!
//! Modes beyond the requested count keep ringing with zero input until they have decayed,
//! so lowering the mode count never clicks.
//!
//! ## Level of detail (docs/MODEL.md "Speed and accuracy")
//! * **Budget**: the [`Quality`] caps the explicit modes ([`Quality::max_modes`]) and the
//!   high band's slots ([`Quality::high_slots`]); `reference` plays every mode explicitly.
//! * **Culling**: an explicit mode whose level (aₖ·eₖ·mₖ)²·τₖ (its share of the output
//!   power under a broadband excitation) lies more than [`Quality::cull_db`] below the
//!   loudest mode's gets no input; like a mode above Nyquist it keeps its pole and rings
//!   out, and it is processed only while it rings. The normalization still counts it, so
//!   culling never changes the loudness. Because the input gain is real (see
//!   [`crate::object::bank`]), switching a mode's input on or off reaches the output only through
//!   its rotation: culling and un-culling never click. (A fitted object played with its
//!   phases has complex gains, whose imaginary part reaches the output at once; its gains
//!   move only with the quality and the material's tilt, never with the ball.)
//! * **Silence**: when the bank has rung out (all state flushed to zero) and a chunk's
//!   input is exactly zero, [`Object::process_chunk`] writes zeros without touching a mode.
//!
//! ## Updates
//! Poles are recomputed only when the material, size, decay, shape, mode count or quality
//! move; the pickups' gains when the listening point or the width move; the input gains
//! when the ball moves (a few multiply–adds per mode: the mode shapes come from
//! recurrences, not a sine per mode).

use crate::analysis::third_octave::BANDS;
use crate::object::bank::{phasor_coeffs, ModalBank, ModeCoeffs};
use crate::object::fitted::{LoadedObject, BAND_MODES, SIDE_SPREAD, TILT_REF_HZ};
use crate::object::kernels::LANES;
use crate::object::long_bank::{LongBank, LONG_MODE_SAMPLES};
use crate::object::material::Material;
use crate::object::quality::{Quality, HIGH_SLOTS_MAX};
use crate::object::shape::{PositionShapes, Shape, ShapeTables, MAX_MODES, REFERENCE_MODES};
use crate::params::{ParamId, Params};
use crate::smooth::Smoother;
use crate::stage::Stage;
use std::sync::Arc;

mod gains;
mod glide;
mod poles;
mod process;
pub mod turn;

/// Output level constant G (calibrated so the default scene plays around −20 dBFS RMS).
pub const OBJECT_LEVEL: f64 = 300.0;

/// Lowest mode frequency (Hz) the object will sound: first modes of huge objects below this
/// are dropped like modes above Nyquist.
pub const MIN_MODE_HZ: f64 = 10.0;

/// The object's modes are carried up to min(Nyquist, this) by the high band and the
/// `reference` quality: the audible band, the same at every sample rate.
pub const HIGH_BAND_TOP_HZ: f64 = 24_000.0;

/// Modes of a high-band group sampled to estimate its energy at the ball and the pickups.
pub const HIGH_SAMPLES: usize = 16;

/// Distance of each pickup from the listening point along x (normalised coordinates: the
/// pair spans half the object).
pub const PICKUP_HALF_SPACING: f64 = 0.5;

/// Bank slot of the first high-band representative (after every explicit mode).
const HIGH_BASE: usize = REFERENCE_MODES;

/// Most modes run in f64 at once ([`LongBank`]); further long modes stay in the f32 bank.
pub const LONG_MODES_MAX: usize = 64;

/// No long slot.
const NOT_LONG: u8 = u8::MAX;

/// The object controls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ObjectControls {
    /// Material disk x ∈ [−1, 1].
    pub material_x: f64,
    /// Material disk y ∈ [−1, 1].
    pub material_y: f64,
    /// Characteristic size in metres; f₁ = 100 Hz·(1 m/size).
    pub size_m: f64,
    /// Mode series.
    pub shape: Shape,
    /// Requested number of explicit modes (1…256).
    pub modes: usize,
    /// Decay time multiplier.
    pub decay: f64,
    /// The listening point (normalised), the centre of the two pickups.
    pub listen: (f64, f64),
    /// Stereo width w ∈ [0, 1].
    pub width: f64,
}

impl Default for ObjectControls {
    fn default() -> Self {
        Self {
            material_x: 0.8,
            material_y: 0.0,
            size_m: 1.0,
            shape: Shape::Plate,
            modes: 32,
            decay: 1.0,
            listen: (-0.2, -0.4),
            width: 1.0,
        }
    }
}

/// First-mode frequency for an object of `size_m` metres: f₁ = 100 Hz·(1 m/size).
#[inline]
pub fn first_mode_hz(size_m: f64) -> f64 {
    100.0 / size_m.max(1e-3)
}

/// The two pickups for a listening point: ±[`PICKUP_HALF_SPACING`] along x, reflected at
/// the edges (normalised coordinates).
pub fn pickups(listen: (f64, f64)) -> [(f64, f64); 2] {
    let reflect = |x: f64| {
        if x > 1.0 {
            2.0 - x
        } else if x < -1.0 {
            -2.0 - x
        } else {
            x
        }
    };
    let (x, y) = (listen.0.clamp(-1.0, 1.0), listen.1.clamp(-1.0, 1.0));
    [
        (reflect(x - PICKUP_HALF_SPACING), y),
        (reflect(x + PICKUP_HALF_SPACING), y),
    ]
}

/// One computed mode (for tests, the editor and analysis).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModeInfo {
    /// Frequency in Hz.
    pub freq_hz: f64,
    /// 1/e decay time in seconds.
    pub decay_s: f64,
    /// Input gain gₖ (the mid gain folded in; 0 for a dropped or culled mode; negative
    /// where the ball sits on a negative lobe of the mode shape).
    pub gain: f64,
    /// Side weight dₖ: the left channel hears gₖ·(1 + dₖ), the right gₖ·(1 − dₖ).
    pub side: f64,
}

impl ModeInfo {
    const SILENT: ModeInfo = ModeInfo {
        freq_hz: 0.0,
        decay_s: 0.0,
        gain: 0.0,
        side: 0.0,
    };

    /// The mode's gain at the left and right channel: gₖ·(1 ± dₖ).
    pub fn gains_lr(&self) -> (f64, f64) {
        (self.gain * (1.0 + self.side), self.gain * (1.0 - self.side))
    }
}

/// A group of high-band modes and its representative.
#[derive(Clone, Copy, Debug)]
struct HighGroup {
    /// Modes in the group.
    count: usize,
    /// Table indices of the sampled modes.
    samples: [usize; HIGH_SAMPLES],
    n_samples: usize,
    /// aₖ²·τₖ of each sample.
    weight: [f64; HIGH_SAMPLES],
    /// Pickup gains qᴸ, qᴿ of each sample.
    pick: [[f64; 2]; HIGH_SAMPLES],
    /// The representative.
    info: ModeInfo,
}

impl HighGroup {
    const EMPTY: HighGroup = HighGroup {
        count: 0,
        samples: [0; HIGH_SAMPLES],
        n_samples: 0,
        weight: [0.0; HIGH_SAMPLES],
        pick: [[0.0; 2]; HIGH_SAMPLES],
        info: ModeInfo::SILENT,
    };
}

/// The resonant object.
///
/// # Allocation
/// `new` and `set_sample_rate` allocate the shape tables and the bank; nothing else
/// allocates.
#[derive(Clone, Debug)]
pub struct Object {
    fs: f64,
    tables: &'static ShapeTables,
    bank: ModalBank,
    /// Modes whose decay outlasts the f32 bank's precision ([`LONG_MODE_SAMPLES`]).
    long: LongBank,
    /// Per bank slot, its slot in `long` (or [`NOT_LONG`]).
    long_of: Vec<u8>,
    /// Per long slot, its bank slot.
    long_slot: [usize; LONG_MODES_MAX],
    /// Some long slot held non-zero state after the last flush.
    long_ringing: bool,
    /// Explicit modes, by table index.
    info: Vec<ModeInfo>,
    /// aₖ (0: not sounding) of each explicit mode.
    amp: Vec<f64>,
    /// Imaginary part of a fitted mode's complex gain, as `amp` (0: sine phase, recipes).
    amp_im: Vec<f64>,
    /// Pickup gains qᴸ, qᴿ of each explicit mode.
    pick: Vec<[f64; 2]>,
    high: [HighGroup; HIGH_SLOTS_MAX],
    n_high: usize,
    shape: Shape,
    /// Explicit modes in use (the request capped by the quality).
    modes: usize,
    /// Modes of the table below min(Nyquist, [`HIGH_BAND_TOP_HZ`]) at the last pole update.
    top: usize,
    material_x: Smoother,
    material_y: Smoother,
    /// Smoothed in log(size) so glides are even in pitch.
    log_size: Smoother,
    log_decay: Smoother,
    listen_x: Smoother,
    listen_y: Smoother,
    width: Smoother,
    ball: (f64, f64),
    ball_shapes: PositionShapes,
    pick_shapes: [PositionShapes; 2],
    poles_dirty: bool,
    pickups_dirty: bool,
    gains_dirty: bool,
    high_band: bool,
    quality: Quality,
    /// The mode count asked for (`modes` is this capped by the quality).
    requested: usize,
    /// Power ratio under which a mode is culled (0: never).
    cull_ratio: f64,
    /// Modes currently culled (sounding but given no input).
    culled: usize,
    /// A fitted object played instead of the shape × material × size recipe
    /// ([`fitted`]).
    loaded: Option<Arc<LoadedObject>>,
    /// The level normalization of the last gain update (input gain per unit of mode
    /// amplitude).
    norm: f64,
    /// A fitted object's gliding modes (empty otherwise: nothing is paid for them).
    glides: glide::Glides,
    /// A shell's doublets turning with a rubbing contact ([`turn`]).
    turn: Box<turn::Turn>,
    /// What each bank slot is to the turning pairs.
    turn_member: Vec<gains::TurnMember>,
    /// The pickups' balance factors (left, right) of the last pickup update.
    balance: [f64; 2],
}

impl Object {
    /// An object at `sample_rate_hz` (sanitized).
    pub fn new(sample_rate_hz: f64, c: ObjectControls) -> Self {
        let tables = ShapeTables::shared();
        let max_index = Shape::ALL
            .iter()
            .map(|&s| {
                let (a, b) = tables.max_index(s);
                a.max(b)
            })
            .max()
            .unwrap_or(1);
        let mut o = Self {
            fs: crate::block::sanitize_sample_rate(sample_rate_hz),
            tables,
            bank: ModalBank::new(HIGH_BASE + HIGH_SLOTS_MAX),
            long: LongBank::new(LONG_MODES_MAX),
            long_of: vec![NOT_LONG; HIGH_BASE + HIGH_SLOTS_MAX],
            long_slot: [0; LONG_MODES_MAX],
            long_ringing: false,
            info: vec![ModeInfo::SILENT; REFERENCE_MODES],
            amp: vec![0.0; REFERENCE_MODES],
            amp_im: vec![0.0; REFERENCE_MODES],
            pick: vec![[0.0; 2]; REFERENCE_MODES],
            high: [HighGroup::EMPTY; HIGH_SLOTS_MAX],
            n_high: 0,
            shape: c.shape,
            modes: c.modes.clamp(1, MAX_MODES),
            top: 0,
            material_x: Smoother::new(c.material_x),
            material_y: Smoother::new(c.material_y),
            log_size: Smoother::new(c.size_m.max(1e-3).ln()),
            log_decay: Smoother::new(c.decay.max(1e-3).ln()),
            listen_x: Smoother::new(c.listen.0),
            listen_y: Smoother::new(c.listen.1),
            width: Smoother::new(c.width),
            ball: (0.3, 0.2),
            ball_shapes: PositionShapes::new(max_index),
            pick_shapes: [
                PositionShapes::new(max_index),
                PositionShapes::new(max_index),
            ],
            poles_dirty: true,
            pickups_dirty: true,
            gains_dirty: true,
            high_band: true,
            quality: Quality::default(),
            requested: c.modes.clamp(1, MAX_MODES),
            cull_ratio: db_to_power(Quality::default().cull_db()),
            culled: 0,
            loaded: None,
            norm: 0.0,
            glides: glide::Glides::default(),
            turn: Box::new(turn::Turn::new()),
            turn_member: vec![gains::TurnMember::None; REFERENCE_MODES],
            balance: [1.0, 1.0],
        };
        o.set_controls(c);
        o.snap_controls();
        o
    }

    /// Change the sample rate (allocates the bank) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::block::sanitize_sample_rate(sample_rate_hz);
        self.bank = ModalBank::new(HIGH_BASE + HIGH_SLOTS_MAX);
        self.long = LongBank::new(LONG_MODES_MAX);
        self.long_of.iter_mut().for_each(|x| *x = NOT_LONG);
        self.long_ringing = false;
        let on = self.turn.on;
        *self.turn = turn::Turn::new();
        self.turn.on = on;
        self.poles_dirty = true;
        self.gains_dirty = true;
        self.update();
    }

    /// Silence the object and jump the controls to their targets (real-time safe).
    pub fn reset(&mut self) {
        self.bank.reset();
        self.long.reset();
        self.long_ringing = false;
        self.turn.reset();
        self.snap_controls();
    }

    /// Let a shell's standing waves turn with the contact ([`turn`]: a finger rubbed round
    /// a rim) or hold them still (the default). Applies at the next chunk; no effect on
    /// other shapes or a fitted object. Real-time safe.
    pub fn set_turning(&mut self, on: bool) {
        if on != self.turn.on {
            self.turn.on = on;
            self.gains_dirty = true;
        }
    }

    /// Set the control targets (continuous ones are smoothed; shape and mode count apply at
    /// the next chunk).
    pub fn set_controls(&mut self, c: ObjectControls) {
        self.material_x.set_target(c.material_x.clamp(-1.0, 1.0));
        self.material_y.set_target(c.material_y.clamp(-1.0, 1.0));
        self.log_size.set_target(c.size_m.clamp(0.01, 100.0).ln());
        self.log_decay.set_target(c.decay.clamp(1e-3, 1e3).ln());
        self.listen_x.set_target(c.listen.0.clamp(-1.0, 1.0));
        self.listen_y.set_target(c.listen.1.clamp(-1.0, 1.0));
        self.width.set_target(c.width.clamp(0.0, 1.0));
        self.requested = c.modes.clamp(1, MAX_MODES);
        if self.loaded.is_some() {
            // A fitted object has no series: shape and mode count wait for the recipe.
            self.shape = c.shape;
            return;
        }
        let modes = self.explicit_count();
        if c.shape != self.shape || modes != self.modes {
            self.shape = c.shape;
            self.modes = modes;
            self.poles_dirty = true;
        }
    }

    fn explicit_count(&self) -> usize {
        if self.quality == Quality::Reference {
            REFERENCE_MODES
        } else {
            self.requested.min(self.quality.max_modes())
        }
    }

    /// Where the ball is (normalised coordinates): the excitation point of every mode.
    /// Applies at the next chunk. Real-time safe.
    pub fn set_ball(&mut self, position: (f64, f64)) {
        let p = (
            if position.0.is_finite() {
                position.0.clamp(-1.0, 1.0)
            } else {
                0.0
            },
            if position.1.is_finite() {
                position.1.clamp(-1.0, 1.0)
            } else {
                0.0
            },
        );
        if p != self.ball {
            self.ball = p;
            // A fitted object has no mode shapes: the ball's place changes nothing.
            self.gains_dirty |= self.loaded.is_none();
        }
    }

    /// The ball position the gains were computed for.
    pub fn ball(&self) -> (f64, f64) {
        self.ball
    }

    /// Set the budget (mode cap, high-band slots, culling threshold; applies at the next
    /// chunk, modes beyond the cap ring out). Real-time safe.
    pub fn set_quality(&mut self, quality: Quality) {
        if quality != self.quality {
            self.quality = quality;
            if self.loaded.is_none() {
                self.modes = self.explicit_count();
            }
            self.poles_dirty = true;
            self.set_cull_db(quality.cull_db());
        }
    }

    /// The budget in force.
    pub fn quality(&self) -> Quality {
        self.quality
    }

    /// Switch the high band on (the default) or off — for measuring what it costs and what
    /// it adds. Applies at the next chunk; its modes ring out. Real-time safe.
    pub fn set_high_band(&mut self, on: bool) {
        if on != self.high_band {
            self.high_band = on;
            self.poles_dirty = true;
        }
    }

    /// Override the culling threshold in dB below the loudest mode (−∞ disables culling;
    /// values above 0 are treated as 0). Applies at the next chunk. Real-time safe.
    pub fn set_cull_db(&mut self, db: f64) {
        let ratio = db_to_power(db);
        if ratio != self.cull_ratio {
            self.cull_ratio = ratio;
            self.gains_dirty = true;
        }
    }

    /// Number of modes culled at the last gain update (below the threshold: no input,
    /// ringing out). A new threshold applies, and is counted, at the next chunk.
    pub fn culled_modes(&self) -> usize {
        self.culled
    }

    /// True when the object has rung out: every processed mode's state is zero, so a zero
    /// input gives exact zeros.
    pub fn is_silent(&self) -> bool {
        self.bank.is_silent() && !self.long_ringing && !self.turn.ringing()
    }

    fn smoothers(&self) -> [&Smoother; 7] {
        [
            &self.material_x,
            &self.material_y,
            &self.log_size,
            &self.log_decay,
            &self.listen_x,
            &self.listen_y,
            &self.width,
        ]
    }

    /// True when a chunk of zero input would change nothing: rung out, no control gliding,
    /// no recomputation due. Its output is then exact zeros.
    pub fn is_idle(&self) -> bool {
        self.is_silent()
            && !(self.poles_dirty || self.pickups_dirty || self.gains_dirty)
            && !self.smoothers().iter().any(|s| s.is_moving())
    }

    /// Mode·samples the bank has processed since `new` (see
    /// [`ModalBank::mode_samples`]): the object's work, for tests and benches.
    pub fn mode_samples(&self) -> u64 {
        self.bank.mode_samples() + self.long.mode_samples()
    }

    /// Modes running in f64 (decays longer than [`LONG_MODE_SAMPLES`] samples).
    pub fn long_modes(&self) -> usize {
        self.long.used()
    }

    /// True when bank slot `k` holds state, in the f32 bank or in the long bank.
    fn slot_ringing(&self, k: usize) -> bool {
        match self.long_of[k] {
            NOT_LONG => self.bank.energy(k) > 0.0,
            j => self.long.energy(usize::from(j)) > 0.0,
        }
    }

    /// Jump the smoothed controls to their targets and recompute the modes.
    pub fn snap_controls(&mut self) {
        self.material_x.snap_to_target();
        self.material_y.snap_to_target();
        self.log_size.snap_to_target();
        self.log_decay.snap_to_target();
        self.listen_x.snap_to_target();
        self.listen_y.snap_to_target();
        self.width.snap_to_target();
        self.poles_dirty = true;
        self.update();
    }

    /// The explicit modes (table order; dropped modes have gain 0).
    pub fn modes(&self) -> &[ModeInfo] {
        let n = self.modes.min(self.info.len());
        &self.info[..n]
    }

    /// The high band's representative modes (their gains carry their groups' energy).
    pub fn high_band(&self) -> impl Iterator<Item = ModeInfo> + '_ {
        self.high[..self.n_high].iter().map(|g| g.info)
    }

    /// Number of modes of the series the high band stands for.
    pub fn high_band_modes(&self) -> usize {
        self.high[..self.n_high].iter().map(|g| g.count).sum()
    }

    /// Number of modes the bank currently processes (explicit ones plus any still ringing
    /// out, and the high band).
    pub fn active_modes(&self) -> usize {
        self.bank.active() + self.bank.tail().1
    }

    /// The stereo width in force (smoothed).
    pub fn width(&self) -> f64 {
        self.width.value()
    }

    /// Play a fitted object instead of the recipe (`None`: back to the recipe). Real-time
    /// safe: no allocation; returns the previous fitted object, so the caller can drop it
    /// off the audio thread. Applies at the next chunk; modes that no longer sound ring out
    /// with no input (no click).
    pub fn set_loaded(&mut self, object: Option<Arc<LoadedObject>>) -> Option<Arc<LoadedObject>> {
        let old = core::mem::replace(&mut self.loaded, object);
        self.amp_im.iter_mut().for_each(|h| *h = 0.0);
        if self.loaded.is_none() {
            self.modes = self.explicit_count();
        }
        self.poles_dirty = true;
        self.pickups_dirty = true;
        self.gains_dirty = true;
        old
    }

    /// The fitted object in play, if any.
    pub fn loaded(&self) -> Option<&Arc<LoadedObject>> {
        self.loaded.as_ref()
    }

    /// The input gain per unit of mode amplitude of the last gain update: the object's
    /// impulse response divided by this is Σ aₖ·e^{−t/τₖ}·sin(2πfₖt) in the amplitudes'
    /// own units (for a fitted object, the recording's full scale; with its phases,
    /// Σ aₖ·e^{−t/τₖ}·cos(2πfₖt + φₖ)).
    pub fn gain_norm(&self) -> f64 {
        self.norm
    }

    fn update(&mut self) {
        if self.loaded.is_some() {
            if self.poles_dirty {
                self.update_poles_loaded();
            }
            self.pickups_dirty = false;
            if self.gains_dirty {
                self.update_gains_loaded();
            }
            return;
        }
        if self.poles_dirty {
            self.update_poles();
        }
        if self.pickups_dirty {
            self.update_pickups();
        }
        if self.gains_dirty {
            self.update_gains();
        }
    }
}

/// A level in dB (≤ 0) as a power ratio; −∞ (or NaN) gives 0.
fn db_to_power(db: f64) -> f64 {
    if db.is_nan() {
        0.0
    } else {
        10f64.powf(db.min(0.0) / 10.0)
    }
}

impl ObjectControls {
    /// The object controls in a parameter set.
    pub fn from_params(p: &Params) -> Self {
        Self {
            material_x: p.get(ParamId::MaterialX),
            material_y: p.get(ParamId::MaterialY),
            size_m: p.get(ParamId::ObjectSize),
            shape: p.shape(),
            modes: p.modes(),
            decay: p.get(ParamId::Decay),
            listen: (p.get(ParamId::ListenX), p.get(ParamId::ListenY)),
            width: p.width(),
        }
    }
}

impl Stage for Object {
    /// The chunk of force the object hears, and its mid and side out (overwritten).
    type Io<'a> = (&'a [f32], &'a mut [f32], &'a mut [f32]);

    fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        Object::set_sample_rate(self, sample_rate_hz);
    }

    fn reset(&mut self, _seed: u64) {
        Object::reset(self);
    }

    fn set_params(&mut self, params: &Params) {
        self.set_quality(params.quality());
        self.set_controls(ObjectControls::from_params(params));
    }

    fn snap(&mut self) {
        self.snap_controls();
    }

    fn is_idle(&self) -> bool {
        Object::is_idle(self)
    }

    fn process(&mut self, (force, mid, side): (&[f32], &mut [f32], &mut [f32])) {
        self.process_chunk_stereo(force, mid, side);
    }
}

#[cfg(test)]
mod tests;
