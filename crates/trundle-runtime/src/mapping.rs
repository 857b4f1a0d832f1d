//! A contact → Trundle's controls: which action it is (an impact when the bodies strike, a
//! roll while the ball turns with the surface, a rub while it slides) and the voice's
//! parameters (speed, ball size, load, the action disk, the touched body's material).
//!
//! Rolling is told from sliding by the slip ratio s = |v − r·ω| / max(v, r·ω): 0 when the
//! contact point is at rest on the surface (pure rolling, v = r·ω), 1 when the ball slides
//! without turning. The action disk's point moves along the chord from *roll* (s = 0) to
//! *rub* (s = 1) (the action disk, CMJ eqs 8-11: inside the disk the parameter sets blend).

use crate::contact::{Contact, Material};
use crate::error::RuntimeError;
use trundle_dsp::params::{ParamId, Params};
use trundle_dsp::source::chain::{ROLL_X, ROLL_Y};

/// What a contact is doing in a frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactKind {
    /// The bodies struck (this frame).
    Impact,
    /// The ball turns with the surface (slip below [`Mapping::rub_slip`]).
    Roll,
    /// The ball slides (slip at or above [`Mapping::rub_slip`]).
    Rub,
}

impl ContactKind {
    /// Its name in logs: `impact`, `roll`, `rub`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Impact => "impact",
            Self::Roll => "roll",
            Self::Rub => "rub",
        }
    }
}

/// The action disk's rub point (angle 0).
const RUB_X: f64 = 1.0;
const RUB_Y: f64 = 0.0;

/// How contacts become controls; the defaults suit balls of a few centimetres.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mapping {
    /// A normal approach faster than this strikes (m/s).
    pub impact_speed_m_s: f64,
    /// Below this speed (sliding, turning and approaching) the contact is at rest (m/s).
    pub rest_speed_m_s: f64,
    /// Slip ratio from which a contact rubs rather than rolls.
    pub rub_slip: f64,
    /// The ball radius heard as size 1 (m); smaller balls scale down (size ≥ 0.1).
    pub full_size_radius_m: f64,
    /// The load heard at 0 dB (N): heavier contacts are louder, +6 dB at most.
    pub reference_load_n: f64,
    /// Speed scale: the voice's velocity control is this × the rolling speed (m/s).
    pub speed_scale: f64,
}

impl Default for Mapping {
    fn default() -> Self {
        Self {
            impact_speed_m_s: 0.1,
            rest_speed_m_s: 0.01,
            rub_slip: 0.4,
            full_size_radius_m: 0.05,
            reference_load_n: 0.5,
            speed_scale: 1.0,
        }
    }
}

impl Mapping {
    /// Check the settings (finite, positive where they must be).
    pub fn validate(&self) -> Result<(), RuntimeError> {
        let fields = [
            ("impact_speed_m_s", self.impact_speed_m_s),
            ("rest_speed_m_s", self.rest_speed_m_s),
            ("rub_slip", self.rub_slip),
            ("full_size_radius_m", self.full_size_radius_m),
            ("reference_load_n", self.reference_load_n),
            ("speed_scale", self.speed_scale),
        ];
        for (what, v) in fields {
            if !(v.is_finite() && v > 0.0) {
                return Err(RuntimeError::BadValue(what, v));
            }
        }
        Ok(())
    }

    /// The slip ratio of `c`, 0 (rolling) … 1 (sliding).
    pub fn slip(&self, c: &Contact) -> f64 {
        let v = c.tangential_speed_m_s;
        let rw = c.radius_m * c.angular_speed_rad_s;
        let top = v.max(rw);
        if top < 1e-9 {
            0.0
        } else {
            ((v - rw).abs() / top).min(1.0)
        }
    }

    /// Rolling or rubbing (impacts are told by the tracker, from the approach speed).
    pub fn motion(&self, c: &Contact) -> ContactKind {
        if self.slip(c) < self.rub_slip {
            ContactKind::Roll
        } else {
            ContactKind::Rub
        }
    }

    /// Does `c` strike (approach faster than [`Mapping::impact_speed_m_s`])?
    pub fn strikes(&self, c: &Contact) -> bool {
        c.normal_speed_m_s > self.impact_speed_m_s
    }

    /// Is `c` at rest (every speed under [`Mapping::rest_speed_m_s`])?
    pub fn rests(&self, c: &Contact) -> bool {
        let r = self.rest_speed_m_s;
        c.tangential_speed_m_s < r
            && c.radius_m * c.angular_speed_rad_s < r
            && c.normal_speed_m_s < r
    }

    /// The rolling speed heard (m/s): the larger of the centre's speed and r·ω.
    pub fn speed_m_s(&self, c: &Contact) -> f64 {
        c.tangential_speed_m_s
            .max(c.radius_m * c.angular_speed_rad_s)
    }

    /// The voice's parameters for `c` touching `surface`, with load `load_n` (N, smoothed
    /// by the caller), on top of `base`. Every value is clamped into its range, so a valid
    /// contact always maps.
    pub fn params(&self, base: &Params, c: &Contact, surface: &Material, load_n: f64) -> Params {
        let mut p = *base;
        // The material was validated when registered: its values are in range.
        let _ = surface.apply(&mut p);
        let speed = (self.speed_scale * self.speed_m_s(c)).clamp(0.0, 1.0);
        p.set_clamped(ParamId::Velocity, speed);
        p.set_clamped(
            ParamId::Size,
            (c.radius_m / self.full_size_radius_m).clamp(0.1, 1.0),
        );
        let s = self.slip(c);
        let blend = if s < self.rub_slip {
            0.0
        } else {
            ((s - self.rub_slip) / (1.0 - self.rub_slip).max(1e-9)).clamp(0.0, 1.0)
        };
        p.set_clamped(ParamId::ActionX, ROLL_X + blend * (RUB_X - ROLL_X));
        p.set_clamped(ParamId::ActionY, ROLL_Y + blend * (RUB_Y - ROLL_Y));
        let load_db = 10.0 * (load_n.max(1e-6) / self.reference_load_n).log10();
        p.set_clamped(
            ParamId::GainDb,
            base.get(ParamId::GainDb) + load_db.clamp(-18.0, 6.0),
        );
        p
    }

    /// How loud a contact is, for the voice budget: the speed it rolls at, or the speed it
    /// strikes with, whichever is larger, weighted by its load.
    pub fn loudness(&self, c: &Contact, load_n: f64) -> f64 {
        let load = (load_n / self.reference_load_n).clamp(0.1, 4.0).sqrt();
        self.speed_m_s(c).max(c.normal_speed_m_s.max(0.0)) * load
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slip_tells_rolling_from_sliding() {
        let m = Mapping::default();
        let mut c = Contact::new(1, 1);
        c.radius_m = 0.02;
        c.tangential_speed_m_s = 0.4;
        c.angular_speed_rad_s = 20.0; // r·ω = 0.4: rolling
        assert!(m.slip(&c) < 1e-12);
        assert_eq!(m.motion(&c), ContactKind::Roll);
        c.angular_speed_rad_s = 0.0; // no spin: sliding
        assert_eq!(m.slip(&c), 1.0);
        assert_eq!(m.motion(&c), ContactKind::Rub);
        let p = m.params(&Params::default(), &c, &Material::wood(), 0.5);
        assert!((p.get(ParamId::ActionX) - RUB_X).abs() < 1e-12);
        assert!((p.get(ParamId::Velocity) - 0.4).abs() < 1e-12);
    }
}
