//! The contact stream's records as Python classes: `Contact` (one touching pair in one
//! physics frame), `Material` (what a body rings and rubs as) and `Listener` (where the
//! stereo image is heard from), each a `trundle_runtime` value with keyword arguments.

use crate::value_error;
use pyo3::prelude::*;
use trundle_dsp::params::{ParamEnum, ParamId, Shape};
use trundle_runtime as rt;

/// One contact pair in one physics frame, in SI units, as a physics engine knows it.
///
/// `Contact(pair, body, normal_speed_m_s=0, tangential_speed_m_s=0, angular_speed_rad_s=0,
/// radius_m=0.02, point_m=(0, 0, 0), normal=(0, 0, 1), normal_impulse_n_s=0,
/// materials=(0, 0))`: `pair` the engine's id of the touching pair (stable while they
/// touch), `body` the moving body; `materials` the indices (into the stream's materials) of
/// the moving body and of what it touches. Values are checked by `ContactStream.update`.
#[pyclass(module = "trundle", from_py_object)]
#[derive(Clone)]
pub struct Contact {
    /// The runtime's record.
    pub inner: rt::Contact,
}

#[pymethods]
impl Contact {
    #[new]
    #[pyo3(signature = (pair, body, normal_speed_m_s = 0.0, tangential_speed_m_s = 0.0, angular_speed_rad_s = 0.0, radius_m = 0.02, point_m = [0.0; 3], normal = [0.0, 0.0, 1.0], normal_impulse_n_s = 0.0, materials = [0, 0]))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        pair: u64,
        body: u64,
        normal_speed_m_s: f64,
        tangential_speed_m_s: f64,
        angular_speed_rad_s: f64,
        radius_m: f64,
        point_m: [f64; 3],
        normal: [f64; 3],
        normal_impulse_n_s: f64,
        materials: [rt::MaterialId; 2],
    ) -> Self {
        Self {
            inner: rt::Contact {
                pair,
                body,
                normal_speed_m_s,
                tangential_speed_m_s,
                angular_speed_rad_s,
                radius_m,
                point_m,
                normal,
                normal_impulse_n_s,
                materials,
            },
        }
    }

    /// The engine's id of the pair.
    #[getter]
    fn pair(&self) -> u64 {
        self.inner.pair
    }
    /// The moving body.
    #[getter]
    fn body(&self) -> u64 {
        self.inner.body
    }
    /// Relative normal speed (m/s, positive approaching).
    #[getter]
    fn normal_speed_m_s(&self) -> f64 {
        self.inner.normal_speed_m_s
    }
    /// Speed along the surface (m/s).
    #[getter]
    fn tangential_speed_m_s(&self) -> f64 {
        self.inner.tangential_speed_m_s
    }
    /// Spin about the axis in the contact plane (rad/s).
    #[getter]
    fn angular_speed_rad_s(&self) -> f64 {
        self.inner.angular_speed_rad_s
    }
    /// Rolling radius (m).
    #[getter]
    fn radius_m(&self) -> f64 {
        self.inner.radius_m
    }
    /// Contact point (m, world).
    #[getter]
    fn point_m(&self) -> [f64; 3] {
        self.inner.point_m
    }
    /// Contact normal (world).
    #[getter]
    fn normal(&self) -> [f64; 3] {
        self.inner.normal
    }
    /// Normal impulse over the frame (N·s).
    #[getter]
    fn normal_impulse_n_s(&self) -> f64 {
        self.inner.normal_impulse_n_s
    }
    /// Material indices: (moving body, what it touches).
    #[getter]
    fn materials(&self) -> [rt::MaterialId; 2] {
        self.inner.materials
    }

    fn __repr__(&self) -> String {
        let c = &self.inner;
        format!(
            "Contact(pair={}, body={}, normal_speed_m_s={}, tangential_speed_m_s={}, angular_speed_rad_s={}, radius_m={}, point_m={:?}, normal={:?}, normal_impulse_n_s={}, materials={:?})",
            c.pair, c.body, c.normal_speed_m_s, c.tangential_speed_m_s, c.angular_speed_rad_s,
            c.radius_m, c.point_m, c.normal, c.normal_impulse_n_s, c.materials
        )
    }
}

/// What a body is made of, as Trundle's controls: the object it rings as and its surface.
///
/// `Material(material_x=0.8, material_y=0.0, object_size_m=1.0, shape="plate", decay=1.0,
/// roughness=0.5)` (the material disk: wood at angle 0, metal at 120°, glass at 240°), or
/// one of `Material.wood()`, `Material.metal()`, `Material.glass()`. Out-of-range values
/// raise `ValueError`.
#[pyclass(module = "trundle", from_py_object)]
#[derive(Clone)]
pub struct Material {
    /// The runtime's material.
    pub inner: rt::Material,
}

#[pymethods]
impl Material {
    #[new]
    #[pyo3(signature = (material_x = 0.8, material_y = 0.0, object_size_m = 1.0, shape = "plate", decay = 1.0, roughness = 0.5))]
    fn new(
        material_x: f64,
        material_y: f64,
        object_size_m: f64,
        shape: &str,
        decay: f64,
        roughness: f64,
    ) -> PyResult<Self> {
        let shape = ParamId::Shape
            .spec()
            .parse(shape)
            .map_err(|e| value_error(format!("shape: {e}")))?;
        let inner = rt::Material {
            material_x,
            material_y,
            object_size_m,
            shape: Shape::from_value(shape),
            decay,
            roughness,
        };
        inner.validate().map_err(value_error)?;
        Ok(Self { inner })
    }

    /// A wooden table.
    #[staticmethod]
    fn wood() -> Self {
        Self {
            inner: rt::Material::wood(),
        }
    }

    /// A metal plate or tray.
    #[staticmethod]
    fn metal() -> Self {
        Self {
            inner: rt::Material::metal(),
        }
    }

    /// A glass or ceramic bowl.
    #[staticmethod]
    fn glass() -> Self {
        Self {
            inner: rt::Material::glass(),
        }
    }

    fn __repr__(&self) -> String {
        let m = &self.inner;
        format!(
            "Material(material_x={}, material_y={}, object_size_m={}, shape={:?}, decay={}, roughness={})",
            m.material_x,
            m.material_y,
            m.object_size_m,
            m.shape.name(),
            m.decay,
            m.roughness
        )
    }
}

/// Where the stereo image is heard from: `Listener(position_m=(0, -2, 1), right=(1, 0, 0),
/// reference_distance_m=1.0)` (`right` the listener's right-hand direction; closer than the
/// reference distance the level stops rising).
#[pyclass(module = "trundle", from_py_object)]
#[derive(Clone)]
pub struct Listener {
    /// The runtime's listener.
    pub inner: rt::Listener,
}

#[pymethods]
impl Listener {
    #[new]
    #[pyo3(signature = (position_m = [0.0, -2.0, 1.0], right = [1.0, 0.0, 0.0], reference_distance_m = 1.0))]
    fn new(position_m: [f64; 3], right: [f64; 3], reference_distance_m: f64) -> PyResult<Self> {
        let inner = rt::Listener {
            position_m,
            right,
            reference_distance_m,
        };
        inner.validate().map_err(value_error)?;
        Ok(Self { inner })
    }

    fn __repr__(&self) -> String {
        let l = &self.inner;
        format!(
            "Listener(position_m={:?}, right={:?}, reference_distance_m={})",
            l.position_m, l.right, l.reference_distance_m
        )
    }
}
