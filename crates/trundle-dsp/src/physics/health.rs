//! How well the physics engine's integration resolves the motion: contacts, penetration,
//! impact speeds and the energy balance, accumulated while it runs.

/// How well the integration resolves the motion, measured since the last
/// [`reset`](crate::physics::PhysicsEngine::reset) or [`reset_health`](crate::physics::PhysicsEngine::reset_health).
///
/// Rules of thumb for a step that is too coarse: `min_substeps_per_contact` below ≈ 8, or
/// `energy_error_rel` growing by more than ≈ 10⁻² per second.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PhysicsHealth {
    /// Simulated time (s).
    pub elapsed_s: f64,
    /// Fraction of substeps that end in contact (x > 0).
    pub contact_ratio: f64,
    /// Completed contacts (x > 0 at consecutive substep ends) per second that reached at
    /// least half the static compression (g/κ)^{2/3}: separate impacts.
    pub impacts_per_s: f64,
    /// Completed contacts per second shallower than that (grazes; not in the substep
    /// statistics).
    pub grazes_per_s: f64,
    /// Largest penetration x seen (m).
    pub max_penetration_m: f64,
    /// Mean length of the impacts (see `impacts_per_s`), in substeps.
    pub mean_substeps_per_contact: f64,
    /// Shortest impact, in substeps (0 when none completed): below ≈ 8 the step is too
    /// coarse for the contact.
    pub min_substeps_per_contact: u64,
    /// Mean penetration rate ẋ at the first substep of each impact (m/s): the impact
    /// velocity v_in of TASLP §IV-D (Fig. 7: below 5 cm/s in the paper's simulations).
    pub mean_impact_speed_m_s: f64,
    /// Largest impact velocity (m/s).
    pub max_impact_speed_m_s: f64,
    /// Energy balance error E − E₀ − ∫P dt (J): zero for an exact integration.
    pub energy_error_j: f64,
    /// `energy_error_j` relative to m_e·g₀·relief (g₀ = 9.81 m/s², a fixed scale: the
    /// potential energy of one relief height).
    pub energy_error_rel: f64,
    /// Modes in use (those below the RK4 stability limit).
    pub active_modes: usize,
}

/// Health accumulators.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct HealthAcc {
    pub(super) substeps: u64,
    pub(super) contact_substeps: u64,
    pub(super) grazes: u64,
    pub(super) runs: u64,
    pub(super) run_sum: u64,
    pub(super) run_min: u64,
    pub(super) cur_run: u64,
    pub(super) cur_run_depth_m: f64,
    pub(super) cur_run_speed_m_s: f64,
    pub(super) speed_sum_m_s: f64,
    pub(super) max_speed_m_s: f64,
    pub(super) max_pen_m: f64,
    /// Energy per unit ball mass at the start (J/kg).
    pub(super) e0: f64,
    /// Work integral per unit ball mass at the start (J/kg).
    pub(super) w0: f64,
}
