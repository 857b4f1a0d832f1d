//! Rapier's contacts → the runtime's contact records: for every pair of colliders with an
//! active contact in the narrow phase, the ball's relative normal speed (from the velocities
//! before the step: the approach the solver then stopped), its sliding speed and spin in the
//! contact plane, the contact point and normal, the solver's normal impulse, the materials.

use crate::scene::{Body, Scene};
use rapier3d::prelude::*;
use trundle_runtime::Contact;

/// The velocities of every body before a step (linear, angular).
pub type Before = Vec<(RigidBodyHandle, Vector, Vector)>;

/// Record the velocities before the step.
pub fn velocities(scene: &Scene, out: &mut Before) {
    out.clear();
    for b in &scene.bodies {
        let rb = &scene.world.bodies[b.handle];
        out.push((b.handle, rb.linvel(), rb.angvel()));
    }
}

fn body_of(scene: &Scene, collider: ColliderHandle) -> Option<&Body> {
    let parent = scene.world.colliders.get(collider)?.parent()?;
    scene.bodies.iter().find(|b| b.handle == parent)
}

fn to_f64(v: Vector) -> [f64; 3] {
    [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
}

/// The contacts after a step, `before` holding the velocities before it.
pub fn contacts(scene: &Scene, before: &Before, out: &mut Vec<Contact>) {
    out.clear();
    let velocity_before = |h: RigidBodyHandle| {
        before
            .iter()
            .find(|(b, _, _)| *b == h)
            .map_or(Vector::ZERO, |&(_, v, _)| v)
    };
    for pair in scene.world.narrow_phase.contact_pairs() {
        if !pair.has_any_active_contact() {
            continue;
        }
        let (Some(a), Some(b)) = (
            body_of(scene, pair.collider1),
            body_of(scene, pair.collider2),
        ) else {
            continue;
        };
        // The moving body is a ball; the normal points from it to what it touches.
        let Some(manifold) = pair.manifolds().iter().find(|m| !m.points.is_empty()) else {
            continue;
        };
        let (ball, other, normal) = match (a.radius_m, b.radius_m) {
            (Some(_), _) => (a, b, manifold.data.normal),
            (None, Some(_)) => (b, a, -manifold.data.normal),
            (None, None) => continue,
        };
        let radius = ball.radius_m.unwrap_or(0.0);
        let (rb, ro) = (
            &scene.world.bodies[ball.handle],
            &scene.world.bodies[other.handle],
        );
        let approach = (velocity_before(ball.handle) - velocity_before(other.handle)).dot(normal);
        let v = rb.linvel() - ro.linvel();
        let v_t = v - normal * v.dot(normal);
        let w = rb.angvel() - ro.angvel();
        let w_t = w - normal * w.dot(normal);
        let centre = rb.translation();
        let (c1, _) = pair.collider1.into_raw_parts();
        let (c2, _) = pair.collider2.into_raw_parts();
        let (body, _) = ball.handle.into_raw_parts();
        out.push(Contact {
            pair: (u64::from(c1) << 32) | u64::from(c2),
            body: u64::from(body),
            normal_speed_m_s: f64::from(approach),
            tangential_speed_m_s: f64::from(v_t.length()),
            angular_speed_rad_s: f64::from(w_t.length()),
            radius_m: f64::from(radius),
            point_m: to_f64(centre + normal * radius),
            normal: to_f64(normal),
            normal_impulse_n_s: f64::from(pair.total_impulse_magnitude()),
            materials: [ball.material, other.material],
        });
    }
    // The narrow phase's order is its own: sort by pair for a stable frame.
    out.sort_by_key(|c| c.pair);
}
