//! The per-frame contact record: what a physics engine knows about one touching pair of
//! bodies, and the materials the pair is made of.

use crate::error::RuntimeError;
use trundle_dsp::params::{ParamId, Params, Shape};

/// Index of a [`Material`] registered with the stream.
pub type MaterialId = u16;

/// One contact pair in one physics frame (SI units).
///
/// The first body is the one that rolls, slides or strikes (a ball); the second is what it
/// touches, whose material rings (a table, a bowl). Two moving balls make a pair too.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// The engine's id of the pair, stable while the two bodies touch (and across the
    /// drop-outs the stream bridges).
    pub pair: u64,
    /// The moving body (for the log and the image).
    pub body: u64,
    /// Relative normal speed (m/s), positive when the bodies approach: an impact's strength.
    pub normal_speed_m_s: f64,
    /// Speed of the moving body's centre along the surface, relative to the other body
    /// (m/s, ≥ 0).
    pub tangential_speed_m_s: f64,
    /// The moving body's spin about the axis in the contact plane (rad/s, ≥ 0); rolling
    /// without slip is `tangential_speed_m_s ≈ radius_m × angular_speed_rad_s`.
    pub angular_speed_rad_s: f64,
    /// The moving body's rolling radius (m, > 0).
    pub radius_m: f64,
    /// Contact point in world coordinates (m).
    pub point_m: [f64; 3],
    /// Contact normal (world, any length; only its direction is used).
    pub normal: [f64; 3],
    /// Normal impulse over the frame (N·s, ≥ 0): with the frame time, the load.
    pub normal_impulse_n_s: f64,
    /// `[moving body, what it touches]`.
    pub materials: [MaterialId; 2],
}

impl Contact {
    /// A contact at rest at the origin between materials 0 and 0 (fill in what you know).
    pub fn new(pair: u64, body: u64) -> Self {
        Self {
            pair,
            body,
            normal_speed_m_s: 0.0,
            tangential_speed_m_s: 0.0,
            angular_speed_rad_s: 0.0,
            radius_m: 0.02,
            point_m: [0.0; 3],
            normal: [0.0, 0.0, 1.0],
            normal_impulse_n_s: 0.0,
            materials: [0, 0],
        }
    }

    /// Check every field: finite, speeds and impulse ≥ 0 where they must be, radius > 0,
    /// materials below `material_count`.
    pub fn validate(&self, material_count: usize) -> Result<(), RuntimeError> {
        let finite = |what, v: f64| {
            if v.is_finite() {
                Ok(())
            } else {
                Err(RuntimeError::BadValue(what, v))
            }
        };
        let non_negative = |what, v: f64| {
            finite(what, v)?;
            if v < 0.0 {
                Err(RuntimeError::BadValue(what, v))
            } else {
                Ok(())
            }
        };
        finite("normal_speed_m_s", self.normal_speed_m_s)?;
        non_negative("tangential_speed_m_s", self.tangential_speed_m_s)?;
        non_negative("angular_speed_rad_s", self.angular_speed_rad_s)?;
        non_negative("normal_impulse_n_s", self.normal_impulse_n_s)?;
        if !(self.radius_m.is_finite() && self.radius_m > 0.0) {
            return Err(RuntimeError::BadValue("radius_m", self.radius_m));
        }
        for v in self.point_m.iter().chain(&self.normal) {
            finite("contact point or normal", *v)?;
        }
        for &m in &self.materials {
            if usize::from(m) >= material_count {
                return Err(RuntimeError::Unknown("material", u64::from(m)));
            }
        }
        Ok(())
    }
}

/// What a body is made of, as Trundle's controls: the object it rings as (material disk,
/// size, shape, decay) and its surface (roughness).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Material disk x (wood at angle 0, metal at 2π/3, glass at 4π/3; Aramaki 2011).
    pub material_x: f64,
    /// Material disk y.
    pub material_y: f64,
    /// The object's characteristic length (m): first mode 100 Hz × 1 m / size.
    pub object_size_m: f64,
    /// The object's mode series.
    pub shape: Shape,
    /// Decay time multiplier.
    pub decay: f64,
    /// Surface roughness 0…1.
    pub roughness: f64,
}

impl Material {
    /// A point of the material disk at `angle_rad`, radius 0.8 (as the default wood).
    fn on_disk(angle_rad: f64, object_size_m: f64, shape: Shape, roughness: f64) -> Self {
        Self {
            material_x: 0.8 * angle_rad.cos(),
            material_y: 0.8 * angle_rad.sin(),
            object_size_m,
            shape,
            decay: 1.0,
            roughness,
        }
    }

    /// A wooden table.
    pub fn wood() -> Self {
        Self::on_disk(0.0, 1.0, Shape::Plate, 0.5)
    }

    /// A metal plate or tray.
    pub fn metal() -> Self {
        Self::on_disk(2.0 * std::f64::consts::FRAC_PI_3, 0.6, Shape::Plate, 0.3)
    }

    /// A glass or ceramic bowl.
    pub fn glass() -> Self {
        Self::on_disk(4.0 * std::f64::consts::FRAC_PI_3, 0.3, Shape::Shell, 0.2)
    }

    /// Check the values against the parameter table (ranges, finiteness).
    pub fn validate(&self) -> Result<(), RuntimeError> {
        let mut p = Params::default();
        self.apply(&mut p)
    }

    /// Write this material's controls into `p`.
    pub fn apply(&self, p: &mut Params) -> Result<(), RuntimeError> {
        p.set(ParamId::MaterialX, self.material_x)?;
        p.set(ParamId::MaterialY, self.material_y)?;
        p.set(ParamId::ObjectSize, self.object_size_m)?;
        p.set(ParamId::Shape, self.shape.value())?;
        p.set(ParamId::Decay, self.decay)?;
        p.set(ParamId::Roughness, self.roughness)?;
        Ok(())
    }
}
