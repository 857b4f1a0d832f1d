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
//!   pₖ = |φₖ(pickup)| ([`crate::shape::PositionShapes`]). The two pickups sit
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
//!   (|dₖ| ≤ w) as the mode's side weight ([`crate::modal`]), so L + R is the mono object at
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
//!   [`crate::modal`]), switching a mode's input on or off reaches the output only through
//!   its rotation: culling and un-culling never click.
//! * **Silence**: when the bank has rung out (all state flushed to zero) and a chunk's
//!   input is exactly zero, [`Object::process_chunk`] writes zeros without touching a mode.
//!
//! ## Updates
//! Poles are recomputed only when the material, size, decay, shape, mode count or quality
//! move; the pickups' gains when the listening point or the width move; the input gains
//! when the ball moves (a few multiply–adds per mode: the mode shapes come from
//! recurrences, not a sine per mode).

pub mod fitted;

use crate::material::Material;
use crate::modal::{phasor_coeffs, LongBank, ModalBank, ModeCoeffs, LANES, LONG_MODE_SAMPLES};
use crate::shape::{PositionShapes, Shape, ShapeTables, MAX_MODES, REFERENCE_MODES};
use crate::smooth::Smoother;
use fitted::{LoadedObject, BANDS, BAND_MODES, SIDE_SPREAD, TILT_REF_HZ};
use std::sync::Arc;

/// Output level constant G (calibrated so the default scene plays around −20 dBFS RMS).
pub const OBJECT_LEVEL: f64 = 300.0;

/// Lowest mode frequency (Hz) the object will sound: first modes of huge objects below this
/// are dropped like modes above Nyquist.
pub const MIN_MODE_HZ: f64 = 10.0;

/// The object's modes are carried up to min(Nyquist, this) by the high band and the
/// `reference` quality: the audible band, the same at every sample rate.
pub const HIGH_BAND_TOP_HZ: f64 = 24_000.0;

/// Most high-band slots any quality uses.
pub const HIGH_SLOTS_MAX: usize = 48;

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

pub use crate::params::Quality;

impl Quality {
    /// Largest number of explicit modes the object sounds.
    pub fn max_modes(self) -> usize {
        match self {
            Quality::Draft => 16,
            Quality::Normal => 64,
            Quality::High | Quality::Ultra => MAX_MODES,
            Quality::Reference => REFERENCE_MODES,
        }
    }

    /// Representative modes of the high band (0: none).
    pub fn high_slots(self) -> usize {
        match self {
            Quality::Draft => 8,
            Quality::Normal => 16,
            Quality::High => 24,
            Quality::Ultra => HIGH_SLOTS_MAX,
            Quality::Reference => 0,
        }
    }

    /// Modes whose level is this many dB below the loudest mode's get no input
    /// (−∞: no culling).
    pub fn cull_db(self) -> f64 {
        match self {
            Quality::Draft => -50.0,
            Quality::Normal => -70.0,
            Quality::High => -90.0,
            Quality::Ultra | Quality::Reference => f64::NEG_INFINITY,
        }
    }

    /// The physics engine's RK4 steps per sample: `Some(n)`, or `None` for the automatic
    /// choice ([`crate::engine::auto_oversample`]).
    pub fn physics_oversample(self) -> Option<usize> {
        match self {
            Quality::Draft => Some(1),
            Quality::Normal | Quality::High => None,
            Quality::Ultra | Quality::Reference => Some(crate::physics::MAX_OVERSAMPLE),
        }
    }
}

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
    tables: ShapeTables,
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
}

impl Object {
    /// An object at `sample_rate_hz` (sanitized).
    pub fn new(sample_rate_hz: f64, c: ObjectControls) -> Self {
        let tables = ShapeTables::new();
        let max_index = Shape::ALL
            .iter()
            .map(|&s| {
                let (a, b) = tables.max_index(s);
                a.max(b)
            })
            .max()
            .unwrap_or(1);
        let mut o = Self {
            fs: crate::sanitize_sample_rate(sample_rate_hz),
            tables,
            bank: ModalBank::new(HIGH_BASE + HIGH_SLOTS_MAX),
            long: LongBank::new(LONG_MODES_MAX),
            long_of: vec![NOT_LONG; HIGH_BASE + HIGH_SLOTS_MAX],
            long_slot: [0; LONG_MODES_MAX],
            long_ringing: false,
            info: vec![ModeInfo::SILENT; REFERENCE_MODES],
            amp: vec![0.0; REFERENCE_MODES],
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
        };
        o.set_controls(c);
        o.snap_controls();
        o
    }

    /// Change the sample rate (allocates the bank) and reset.
    pub fn set_sample_rate(&mut self, sample_rate_hz: f64) {
        self.fs = crate::sanitize_sample_rate(sample_rate_hz);
        self.bank = ModalBank::new(HIGH_BASE + HIGH_SLOTS_MAX);
        self.long = LongBank::new(LONG_MODES_MAX);
        self.long_of.iter_mut().for_each(|x| *x = NOT_LONG);
        self.long_ringing = false;
        self.poles_dirty = true;
        self.update();
    }

    /// Silence the object and jump the controls to their targets (real-time safe).
    pub fn reset(&mut self) {
        self.bank.reset();
        self.long.reset();
        self.long_ringing = false;
        self.snap_controls();
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
        self.bank.is_silent() && !self.long_ringing
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

    /// Route the slots whose decay outlasts the f32 bank to the long bank (moving their
    /// state), and the others back; set the long slots' poles.
    fn assign_long_modes(&mut self) {
        let fs = self.fs;
        // The slots that want f64: sounding or ringing, with τ·f_s beyond the limit.
        let mut want = [0usize; LONG_MODES_MAX];
        let mut n_want = 0;
        let explicit = self.modes.max(self.bank.active()).min(self.info.len());
        for slot in (0..explicit).chain(HIGH_BASE..HIGH_BASE + HIGH_SLOTS_MAX) {
            let (live, info) = if slot >= HIGH_BASE {
                let j = slot - HIGH_BASE;
                (j < self.n_high, self.high[j].info)
            } else {
                (self.amp[slot] != 0.0, self.info[slot])
            };
            if (live || self.slot_ringing(slot))
                && info.decay_s * fs > LONG_MODE_SAMPLES
                && info.freq_hz < 0.5 * fs
                && info.freq_hz >= MIN_MODE_HZ
                && n_want < LONG_MODES_MAX
            {
                want[n_want] = slot;
                n_want += 1;
            }
        }
        // Save the long states, release every long slot to the f32 bank.
        let mut saved = [(0usize, 0.0f64, 0.0f64); LONG_MODES_MAX];
        let n_old = self.long.used();
        for (j, sv) in saved.iter_mut().enumerate().take(n_old) {
            let (re, im) = self.long.state(j);
            *sv = (self.long_slot[j], re, im);
            self.long_of[self.long_slot[j]] = NOT_LONG;
        }
        self.long.reset();
        for &(slot, re, im) in &saved[..n_old] {
            if !want[..n_want].contains(&slot) {
                // Back to f32, with its pole.
                let info = self.slot_info(slot);
                let (c, s) = phasor_coeffs(info.freq_hz, info.decay_s, fs);
                let mc = self.bank.mode(slot);
                self.bank.set_mode(slot, ModeCoeffs { c, s, ..mc });
                self.bank.set_state(slot, re as f32, im as f32);
            }
        }
        for (j, &slot) in want[..n_want].iter().enumerate() {
            let info = self.slot_info(slot);
            let (re, im) = match saved[..n_old].iter().find(|x| x.0 == slot) {
                Some(&(_, re, im)) => (re, im),
                None => {
                    let (re, im) = self.bank.state(slot);
                    (f64::from(re), f64::from(im))
                }
            };
            self.long.set_mode(j, info.freq_hz, info.decay_s, fs);
            self.long.set_state(j, re, im);
            self.long_of[slot] = j as u8;
            self.long_slot[j] = slot;
            // The f32 slot falls silent: no pole, no state, no input.
            self.bank.set_mode(slot, ModeCoeffs::default());
            self.bank.set_state(slot, 0.0, 0.0);
        }
        self.long.set_used(n_want);
    }

    fn slot_info(&self, slot: usize) -> ModeInfo {
        if slot >= HIGH_BASE {
            self.high[slot - HIGH_BASE].info
        } else {
            self.info[slot]
        }
    }

    /// Set bank slot `k`'s input gain and side weight, wherever it runs.
    fn set_slot_gains(&mut self, k: usize, g: f64, d: f64) {
        match self.long_of[k] {
            NOT_LONG => self.bank.set_gains(k, g as f32, d as f32),
            j => {
                self.long.set_gains(usize::from(j), g, d);
                self.bank.set_gains(k, 0.0, 0.0);
            }
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
    /// own units (for a fitted object, the recording's full scale).
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

    /// Frequencies, decays, amplitudes and poles of the explicit modes; the high band's
    /// groups and representatives.
    fn update_poles(&mut self) {
        let fs = self.fs;
        let material = Material::from_disk(self.material_x.value(), self.material_y.value());
        let f1 = first_mode_hz(self.log_size.value().exp());
        let decay = self.log_decay.value().exp();
        let table = self.tables.modes(self.shape);
        let nyquist = 0.5 * fs;
        let top_hz = nyquist.min(HIGH_BAND_TOP_HZ);
        let reference = self.quality == Quality::Reference;
        // Explicit modes: those in use, and any beyond that still ring (they keep a valid
        // pole and ring out with no input).
        let span = self.modes.max(self.bank.active()).min(table.len());
        for (k, m) in table.iter().enumerate().take(span) {
            let f = f1 * m.ratio;
            let limit = if reference { top_hz } else { nyquist };
            let sounding = k < self.modes && f < limit && f >= MIN_MODE_HZ;
            let tau = material.decay_s(f, decay);
            self.amp[k] = if sounding {
                m.ratio.powf(material.tilt)
            } else {
                0.0
            };
            self.info[k].freq_hz = f;
            self.info[k].decay_s = tau;
            let ringing = self.slot_ringing(k);
            if (sounding || ringing) && f < nyquist && f >= MIN_MODE_HZ {
                let (c, s) = phasor_coeffs(f, tau, fs);
                let mc = self.bank.mode(k);
                self.bank.set_mode(k, ModeCoeffs { c, s, ..mc });
            } else if !ringing {
                self.bank.set_mode(k, ModeCoeffs::default());
            }
        }
        // The series up to the top of the band.
        let first_high = self.modes.min(table.len());
        let mut top = first_high;
        while top < table.len() && f1 * table[top].ratio < top_hz {
            top += 1;
        }
        self.top = top;
        // High band: groups of the modes first_high..top.
        let slots = if self.high_band && !reference {
            self.quality.high_slots()
        } else {
            0
        };
        let old_high = self.n_high;
        self.n_high = 0;
        let count = top.saturating_sub(first_high);
        if slots > 0 && count > 0 {
            let f_lo = f1 * table[first_high].ratio;
            let span_ln = (top_hz / f_lo).ln().max(1e-9);
            let mut a = first_high;
            while a < top {
                // The group of mode a: its slot by log frequency (or itself when the band
                // has no more modes than slots).
                let b = if count <= slots {
                    a + 1
                } else {
                    let j = ((f1 * table[a].ratio / f_lo).ln() / span_ln * slots as f64)
                        .floor()
                        .min(slots as f64 - 1.0);
                    let mut b = a + 1;
                    while b < top {
                        let jb = ((f1 * table[b].ratio / f_lo).ln() / span_ln * slots as f64)
                            .floor()
                            .min(slots as f64 - 1.0);
                        if jb != j {
                            break;
                        }
                        b += 1;
                    }
                    b
                };
                let g = &mut self.high[self.n_high];
                g.count = b - a;
                g.n_samples = g.count.min(HIGH_SAMPLES);
                for i in 0..g.n_samples {
                    // Evenly spread through the group, centred in each stratum.
                    let k = a + (2 * i + 1) * g.count / (2 * g.n_samples);
                    let f = f1 * table[k].ratio;
                    let tau = material.decay_s(f, decay);
                    g.samples[i] = k;
                    g.weight[i] = table[k].ratio.powf(2.0 * material.tilt) * tau;
                }
                let rep = a + g.count / 2;
                let f = f1 * table[rep].ratio;
                g.info.freq_hz = f;
                g.info.decay_s = material.decay_s(f, decay);
                let (c, s) = phasor_coeffs(f, g.info.decay_s, fs);
                let slot = HIGH_BASE + self.n_high;
                let mc = self.bank.mode(slot);
                self.bank.set_mode(slot, ModeCoeffs { c, s, ..mc });
                self.n_high += 1;
                a = b;
            }
        }
        // Slots no longer used ring out with no input.
        for j in self.n_high..old_high.max(self.n_high) {
            self.high[j].info.gain = 0.0;
        }
        self.assign_long_modes();
        self.poles_dirty = false;
        self.pickups_dirty = true;
    }

    /// Pickup gains of every explicit and sampled high-band mode, balanced per channel.
    fn update_pickups(&mut self) {
        let shape = self.shape;
        let table = self.tables.modes(shape);
        let (mi, ni) = self.tables.max_index(shape);
        let upto = if shape == Shape::Plate {
            // Only the indices the modes in use reach.
            let mut u = 0usize;
            for m in &table[..self.top.max(self.modes).min(table.len())] {
                u = u.max(usize::from(m.m)).max(usize::from(m.n));
            }
            u
        } else {
            mi.max(ni).min(self.top.max(self.modes) + 2)
        };
        let p = pickups((self.listen_x.value(), self.listen_y.value()));
        for (ps, &point) in self.pick_shapes.iter_mut().zip(p.iter()) {
            ps.set(shape, point, upto);
        }
        // Balance: each channel's weighted mean square pickup gain is 1.
        let (mut sum_w, mut sum_l, mut sum_r) = (0.0, 0.0, 0.0);
        for (k, mode) in table.iter().enumerate().take(self.modes) {
            let a = self.amp[k];
            if a == 0.0 {
                continue;
            }
            let pl = self.pick_shapes[0].phi(mode).abs();
            let pr = self.pick_shapes[1].phi(mode).abs();
            self.pick[k] = [pl, pr];
            let w = a * a * self.info[k].decay_s;
            sum_w += w;
            sum_l += w * pl * pl;
            sum_r += w * pr * pr;
        }
        for g in self.high[..self.n_high].iter_mut() {
            let scale = g.count as f64 / g.n_samples as f64;
            for i in 0..g.n_samples {
                let mode = &table[g.samples[i]];
                let pl = self.pick_shapes[0].phi(mode).abs();
                let pr = self.pick_shapes[1].phi(mode).abs();
                g.pick[i] = [pl, pr];
                let w = g.weight[i] * scale;
                sum_w += w;
                sum_l += w * pl * pl;
                sum_r += w * pr * pr;
            }
        }
        let bl = if sum_l > 0.0 {
            (sum_w / sum_l).sqrt()
        } else {
            1.0
        };
        let br = if sum_r > 0.0 {
            (sum_w / sum_r).sqrt()
        } else {
            1.0
        };
        for k in 0..self.modes.min(table.len()) {
            if self.amp[k] != 0.0 {
                self.pick[k] = [self.pick[k][0] * bl, self.pick[k][1] * br];
            }
        }
        for g in self.high[..self.n_high].iter_mut() {
            for i in 0..g.n_samples {
                g.pick[i] = [g.pick[i][0] * bl, g.pick[i][1] * br];
            }
        }
        self.pickups_dirty = false;
        self.gains_dirty = true;
    }

    /// Input gains and side weights from the ball position, the pickups and the width;
    /// the level normalization; culling.
    fn update_gains(&mut self) {
        let shape = self.shape;
        let table = self.tables.modes(shape);
        let upto = self.pick_shapes[0].evaluated().saturating_sub(1);
        self.ball_shapes.set(shape, self.ball, upto);
        let w = self.width.value();
        let n = self.modes.min(table.len());
        // Pre-normalization mid gains, and the total mid energy E.
        let mut energy = 0.0;
        let mut loudest = 0.0f64;
        for (k, mode) in table.iter().enumerate().take(n) {
            let a = self.amp[k];
            if a == 0.0 {
                self.info[k].gain = 0.0;
                self.info[k].side = 0.0;
                continue;
            }
            let e = self.ball_shapes.phi(mode);
            let [ql, qr] = self.pick[k];
            let mid = 0.5 * (ql + qr);
            let x = a * e * mid;
            self.info[k].gain = x;
            self.info[k].side = if mid > 0.0 {
                w * 0.5 * (ql - qr) / mid
            } else {
                0.0
            };
            let p = x * x * self.info[k].decay_s;
            energy += p;
            loudest = loudest.max(p);
        }
        for g in self.high[..self.n_high].iter_mut() {
            let scale = g.count as f64 / g.n_samples as f64;
            let (mut em, mut es, mut lr) = (0.0, 0.0, 0.0);
            for i in 0..g.n_samples {
                let e = self.ball_shapes.phi(&table[g.samples[i]]);
                let [ql, qr] = g.pick[i];
                let we = g.weight[i] * e * e;
                em += we * 0.25 * (ql + qr) * (ql + qr);
                es += we * 0.25 * w * w * (ql - qr) * (ql - qr);
                lr += we * (ql * ql - qr * qr);
            }
            em *= scale;
            es *= scale;
            g.info.gain = (em / g.info.decay_s).sqrt();
            g.info.side = if em > 0.0 {
                (es / em).sqrt().copysign(lr)
            } else {
                0.0
            };
            energy += em;
        }
        let norm = if energy > 0.0 {
            OBJECT_LEVEL / (self.fs * energy.sqrt())
        } else {
            0.0
        };
        self.norm = norm;
        let cull_below = loudest * self.cull_ratio;
        self.culled = 0;
        let mut last_active = 0;
        for k in 0..n.max(self.bank.active()).min(self.info.len()) {
            let sounding = k < n && self.amp[k] != 0.0;
            let info = self.info[k];
            let culled = sounding && info.gain * info.gain * info.decay_s < cull_below;
            self.culled += culled as usize;
            let g = if sounding { info.gain * norm } else { 0.0 };
            self.info[k].gain = g;
            if sounding && !culled {
                self.set_slot_gains(k, g, info.side);
                last_active = k + 1;
            } else {
                // Dropped, beyond the count or culled: no input; a mode still ringing keeps
                // its pole (set in `update_poles`) and rings out at its own rate.
                self.set_slot_gains(k, 0.0, info.side);
                if self.slot_ringing(k) || (sounding && culled) {
                    last_active = k + 1;
                }
            }
        }
        let mut tail = self.n_high;
        for j in 0..HIGH_SLOTS_MAX {
            let slot = HIGH_BASE + j;
            if j < self.n_high {
                self.high[j].info.gain *= norm;
                let info = self.high[j].info;
                self.set_slot_gains(slot, info.gain, info.side);
            } else {
                let d = self.high[j].info.side;
                self.set_slot_gains(slot, 0.0, d);
                if self.slot_ringing(slot) {
                    tail = j + 1;
                }
            }
        }
        self.bank.set_active(last_active.div_ceil(LANES) * LANES);
        self.bank.set_tail(HIGH_BASE, tail);
        self.gains_dirty = false;
    }

    /// Poles of a fitted object ([`fitted`]): its loudest modes up to the quality's cap,
    /// then the band part (the envelope plus the energy of the modes over the cap), every
    /// one modified by `decay`, the material disk and `object_size`.
    fn update_poles_loaded(&mut self) {
        let Some(obj) = self.loaded.clone() else {
            return;
        };
        let fs = self.fs;
        let nyquist = 0.5 * fs;
        let decay = self.log_decay.value().exp();
        let transpose = 1.0 / self.log_size.value().exp();
        let material = Material::from_disk(self.material_x.value(), self.material_y.value());
        let neutral = Material::from_disk(
            crate::params::ParamId::MaterialX.spec().default,
            crate::params::ParamId::MaterialY.spec().default,
        );
        let law = |f: f64| neutral.damping_per_s(f) / material.damping_per_s(f);
        let law_ref = law(TILT_REF_HZ);
        let dtilt = material.tilt - neutral.tilt;
        // τ' = τ·decay·tilt(f), a' = a·(f/f_ref)^Δtilt: exactly τ and a at the defaults.
        let modify = |f: f64, tau: f64, a: f64| {
            let k = if law_ref > 0.0 {
                (law(f) / law_ref).clamp(1.0 / 20.0, 20.0)
            } else {
                1.0
            };
            let k = if k.is_finite() { k } else { 1.0 };
            let tau =
                (tau * decay * k).clamp(crate::material::DECAY_MIN_S, crate::material::DECAY_MAX_S);
            let a = if dtilt == 0.0 {
                a
            } else {
                a * (f / TILT_REF_HZ).powf(dtilt)
            };
            (tau, a)
        };
        let cap = if self.quality == Quality::Reference {
            REFERENCE_MODES - BANDS * BAND_MODES
        } else {
            self.quality.max_modes()
        };
        // Energy (a²τ) and energy × τ of the modes over the cap, per band.
        let mut over = [(0.0f64, 0.0f64); BANDS];
        let mut n = 0usize;
        let span = self.modes.max(self.bank.active()).min(self.info.len());
        let place = |o: &mut Self, k: usize, f: f64, tau: f64, g: f64, side: f64| {
            o.info[k].freq_hz = f;
            o.info[k].decay_s = tau;
            o.amp[k] = g;
            o.pick[k] = [side, 0.0];
            let (c, s) = phasor_coeffs(f, tau, fs);
            let mc = o.bank.mode(k);
            o.bank.set_mode(k, ModeCoeffs { c, s, ..mc });
        };
        for m in obj.modes() {
            let f = m.freq_hz * transpose;
            if !(f < nyquist && f >= MIN_MODE_HZ) {
                continue;
            }
            let (tau, g) = modify(f, m.decay_s, m.gain);
            if n < cap {
                place(self, n, f, tau, g, m.side);
                n += 1;
            } else {
                let e = g * g * tau;
                over[m.band].0 += e;
                over[m.band].1 += e * tau;
            }
        }
        let bands = obj.bands().iter().enumerate().filter(|_| obj.band_part());
        for (i, b) in bands {
            let f_mid = fitted::band_centre_hz(i) * transpose;
            let (tau_env, a_env) = if b.amplitude > 0.0 {
                modify(f_mid, b.decay_s, b.amplitude)
            } else {
                (0.0, 0.0)
            };
            let e_env = a_env * a_env * tau_env * BAND_MODES as f64;
            let e = e_env + over[i].0;
            if e <= 0.0 {
                continue;
            }
            let tau = (e_env * tau_env + over[i].1) / e;
            let a = (e / (BAND_MODES as f64 * tau)).sqrt();
            for j in 0..BAND_MODES {
                let f = LoadedObject::band_mode_hz(i, j) * transpose;
                if f < nyquist && f >= MIN_MODE_HZ {
                    place(
                        self,
                        n,
                        f,
                        tau,
                        a * LoadedObject::band_sign(i, j),
                        obj.band_side(i, j),
                    );
                    n += 1;
                }
            }
        }
        // Slots no longer in use ring out with their pole and no input.
        for k in n..span {
            self.amp[k] = 0.0;
            if !self.slot_ringing(k) {
                self.bank.set_mode(k, ModeCoeffs::default());
            }
        }
        self.modes = n;
        self.top = n;
        let old_high = self.n_high;
        self.n_high = 0;
        for j in 0..old_high {
            self.high[j].info.gain = 0.0;
        }
        self.assign_long_modes();
        self.poles_dirty = false;
        self.pickups_dirty = false;
        self.gains_dirty = true;
    }

    /// Gains and side weights of a fitted object: the recipe's level law (a white force
    /// gives the same loudness), culling, the pseudo-random stereo image ([`fitted`]).
    fn update_gains_loaded(&mut self) {
        let w = self.width.value();
        let n = self.modes;
        let (mut energy, mut loudest) = (0.0f64, 0.0f64);
        for k in 0..n {
            let p = self.amp[k] * self.amp[k] * self.info[k].decay_s;
            energy += p;
            loudest = loudest.max(p);
        }
        let norm = if energy > 0.0 {
            OBJECT_LEVEL / (self.fs * energy.sqrt())
        } else {
            0.0
        };
        self.norm = norm;
        let cull_below = loudest * self.cull_ratio;
        self.culled = 0;
        let mut last_active = 0;
        for k in 0..n.max(self.bank.active()).min(self.info.len()) {
            let sounding = k < n && self.amp[k] != 0.0;
            let a = self.amp[k];
            let culled = sounding && a * a * self.info[k].decay_s < cull_below;
            self.culled += culled as usize;
            let g = if sounding { a * norm } else { 0.0 };
            let d = if sounding {
                w * SIDE_SPREAD * self.pick[k][0]
            } else {
                self.info[k].side
            };
            self.info[k].gain = g;
            self.info[k].side = d;
            if sounding && !culled {
                self.set_slot_gains(k, g, d);
                last_active = k + 1;
            } else {
                self.set_slot_gains(k, 0.0, d);
                if self.slot_ringing(k) || (sounding && culled) {
                    last_active = k + 1;
                }
            }
        }
        let mut tail = 0;
        for j in 0..HIGH_SLOTS_MAX {
            let slot = HIGH_BASE + j;
            let d = self.high[j].info.side;
            self.set_slot_gains(slot, 0.0, d);
            if self.slot_ringing(slot) {
                tail = j + 1;
            }
        }
        self.bank.set_active(last_active.div_ceil(LANES) * LANES);
        self.bank.set_tail(HIGH_BASE, tail);
        self.gains_dirty = false;
    }

    fn advance_controls(&mut self, n: usize) {
        let fs = self.fs;
        let mut poles = false;
        for s in [
            &mut self.material_x,
            &mut self.material_y,
            &mut self.log_size,
            &mut self.log_decay,
        ] {
            if s.is_moving() {
                s.advance(n, fs);
                poles = true;
            }
        }
        let mut pickups = false;
        for s in [&mut self.listen_x, &mut self.listen_y] {
            if s.is_moving() {
                s.advance(n, fs);
                pickups = true;
            }
        }
        if self.width.is_moving() {
            self.width.advance(n, fs);
            self.gains_dirty = true;
        }
        self.poles_dirty |= poles;
        self.pickups_dirty |= pickups;
        self.update();
    }

    /// Filter one chunk of force through the object (`out` overwritten with the mono mix,
    /// the mid).
    pub fn process_chunk(&mut self, force: &[f32], out: &mut [f32]) {
        self.advance_controls(force.len());
        if self.is_silent() && force.iter().all(|&x| x == 0.0) {
            // Rung out and no input: the output is exactly zero; no mode is touched.
            out.iter_mut().for_each(|y| *y = 0.0);
            return;
        }
        self.bank.process(force, out);
        if self.long.used() > 0 {
            self.long.process_add(force, out, None);
        }
        self.after_chunk();
    }

    /// Filter one chunk of force through the object: `mid` and `side` overwritten
    /// (L = mid + side, R = mid − side; `mid` is what [`process_chunk`](Self::process_chunk)
    /// writes). At width 0 the side is zero and costs nothing.
    pub fn process_chunk_stereo(&mut self, force: &[f32], mid: &mut [f32], side: &mut [f32]) {
        self.advance_controls(force.len());
        if self.is_silent() && force.iter().all(|&x| x == 0.0) {
            mid.iter_mut().for_each(|y| *y = 0.0);
            side.iter_mut().for_each(|y| *y = 0.0);
            return;
        }
        if self.width.value() == 0.0 && !self.width.is_moving() {
            self.bank.process(force, mid);
            side.iter_mut().for_each(|y| *y = 0.0);
            if self.long.used() > 0 {
                self.long.process_add(force, mid, None);
            }
        } else {
            self.bank.process_stereo(force, mid, side);
            if self.long.used() > 0 {
                self.long.process_add(force, mid, Some(side));
            }
        }
        self.after_chunk();
    }

    fn after_chunk(&mut self) {
        self.bank.flush();
        self.long_ringing = self.long.flush();
        // Shrink the processed ranges once ringing-out modes have decayed.
        let active = self.bank.active();
        if active > 0 && self.bank.mode(active - 1).g == 0.0 {
            let mut last = 0;
            for k in 0..active {
                if self.bank.mode(k).g != 0.0 || self.slot_ringing(k) || self.long_of[k] != NOT_LONG
                {
                    last = k + 1;
                }
            }
            self.bank.set_active(last.div_ceil(LANES) * LANES);
        }
        let (start, len) = self.bank.tail();
        if len > self.n_high.div_ceil(LANES) * LANES {
            let mut last = self.n_high;
            for k in start..start + len {
                if self.slot_ringing(k) {
                    last = last.max(k - start + 1);
                }
            }
            self.bank.set_tail(HIGH_BASE, last);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modes_follow_shape_size_and_nyquist() {
        let c = ObjectControls {
            size_m: 0.5,
            shape: Shape::String,
            modes: 256,
            ..Default::default()
        };
        let o = Object::new(8_000.0, c);
        let m = o.modes();
        assert!((m[0].freq_hz - 200.0).abs() < 1e-9);
        assert!((m[2].freq_hz - 600.0).abs() < 1e-9);
        // 200·k < 4000 → k ≤ 19 sound; the rest are dropped.
        assert!(m[18].gain != 0.0);
        assert_eq!(m[19].gain, 0.0);
        assert!(o.bank.active() <= 24);
        // Nothing left above the explicit modes at Nyquist: no high band.
        assert_eq!(o.high_band_modes(), 0);
    }

    #[test]
    fn pickups_straddle_the_listening_point_inside_the_object() {
        let [l, r] = pickups((0.0, -0.4));
        assert_eq!((l, r), ((-0.5, -0.4), (0.5, -0.4)));
        let [l, r] = pickups((0.9, 0.0));
        assert!((l.0 - 0.4).abs() < 1e-12 && (r.0 - 0.6).abs() < 1e-12);
    }
}
