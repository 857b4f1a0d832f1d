//! The scene: a wooden table, a glass bowl on it (a triangle mesh), and marbles — one rolled
//! across the table, one dropped on it, two rolled into each other, one dropped into the
//! bowl — in a Rapier world stepped at a fixed rate (deterministic).

use rapier3d::pipeline::PhysicsWorld;
use rapier3d::prelude::*;
use trundle_runtime::{Material, MaterialId};

/// Marble radius (m).
pub const BALL_RADIUS_M: f32 = 0.02;
/// Glass density (kg/m³): a 2 cm marble weighs 84 g.
const GLASS_DENSITY: f32 = 2500.0;
/// The bowl: the lowest point of its inside (m; on a 3 cm foot, so a ball in it never
/// touches the table through it) and its inner radius (m).
pub const BOWL_CENTRE: [f32; 3] = [0.55, 0.03, -0.2];
const BOWL_RADIUS_M: f32 = 0.16;

/// The materials the contacts name, by index.
pub const MARBLE: MaterialId = 0;
/// The table's material.
pub const WOOD: MaterialId = 1;
/// The bowl's material.
pub const GLASS: MaterialId = 2;

/// The runtime's material table for [`MARBLE`], [`WOOD`], [`GLASS`].
pub fn materials() -> Vec<Material> {
    let marble = Material {
        object_size_m: 0.05,
        decay: 0.3,
        roughness: 0.1,
        ..Material::glass()
    };
    vec![marble, Material::wood(), Material::glass()]
}

/// One body of the scene and what it is made of.
#[derive(Clone, Debug)]
pub struct Body {
    /// Its name in the log.
    pub name: &'static str,
    /// Its handle.
    pub handle: RigidBodyHandle,
    /// Its material.
    pub material: MaterialId,
    /// Its radius when it is a ball (m).
    pub radius_m: Option<f32>,
}

/// The world and its bodies.
pub struct Scene {
    /// Rapier's world.
    pub world: PhysicsWorld,
    /// Every body (the table and the bowl included).
    pub bodies: Vec<Body>,
}

fn marble(
    world: &mut PhysicsWorld,
    bodies: &mut Vec<Body>,
    name: &'static str,
    at: [f32; 3],
    linvel: [f32; 3],
) {
    let v = Vector::new(linvel[0], linvel[1], linvel[2]);
    // Rolling without slip on a horizontal table: ω = n × v / r with n up.
    let w = Vector::Y.cross(v) / BALL_RADIUS_M;
    let (handle, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(at[0], at[1], at[2]))
            .linvel(v)
            .angvel(w)
            .linear_damping(0.25)
            .angular_damping(0.25)
            .ccd_enabled(true),
        ColliderBuilder::ball(BALL_RADIUS_M)
            .density(GLASS_DENSITY)
            .friction(0.6)
            .restitution(0.5),
    );
    bodies.push(Body {
        name,
        handle,
        material: MARBLE,
        radius_m: Some(BALL_RADIUS_M),
    });
}

/// A hemispherical bowl of `BOWL_RADIUS_M`, open at the top, as a triangle mesh.
fn bowl_mesh() -> (Vec<Vector>, Vec<[u32; 3]>) {
    let (rings, segments) = (8u32, 24u32);
    let mut vertices = Vec::new();
    for i in 0..=rings {
        // From the bottom (polar angle π) to the rim (π/2).
        let polar = std::f32::consts::PI - (i as f32 / rings as f32) * std::f32::consts::FRAC_PI_2;
        for j in 0..segments {
            let az = j as f32 / segments as f32 * std::f32::consts::TAU;
            let r = BOWL_RADIUS_M * polar.sin();
            vertices.push(Vector::new(
                r * az.cos(),
                BOWL_RADIUS_M + BOWL_RADIUS_M * polar.cos(),
                r * az.sin(),
            ));
        }
    }
    let mut indices = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let a = i * segments + j;
            let b = i * segments + (j + 1) % segments;
            let (c, d) = (a + segments, b + segments);
            indices.push([a, c, b]);
            indices.push([b, c, d]);
        }
    }
    (vertices, indices)
}

/// Build the scene.
pub fn build() -> Scene {
    let mut world = PhysicsWorld::new();
    let mut bodies = Vec::new();
    // The table: 2 m × 1 m, its top at y = 0.
    let table = world.insert_body(RigidBodyBuilder::fixed());
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.05, 0.5)
            .translation(Vector::new(0.0, -0.05, 0.0))
            .friction(0.6)
            .restitution(0.5),
        Some(table),
    );
    bodies.push(Body {
        name: "table",
        handle: table,
        material: WOOD,
        radius_m: None,
    });
    let bowl = world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(
        BOWL_CENTRE[0],
        BOWL_CENTRE[1],
        BOWL_CENTRE[2],
    )));
    let (v, i) = bowl_mesh();
    let mesh = ColliderBuilder::trimesh(v, i).expect("the bowl mesh has triangles");
    world.insert_collider(mesh.friction(0.4).restitution(0.4), Some(bowl));
    bodies.push(Body {
        name: "bowl",
        handle: bowl,
        material: GLASS,
        radius_m: None,
    });
    let r = BALL_RADIUS_M;
    // Rolled across the table, on a lane of its own.
    marble(
        &mut world,
        &mut bodies,
        "roller",
        [-0.9, r, 0.35],
        [0.45, 0.0, 0.0],
    );
    // Dropped from 25 cm with a little drift: bounces, then rolls.
    marble(
        &mut world,
        &mut bodies,
        "dropper",
        [-0.3, 0.25, 0.1],
        [0.15, 0.0, 0.0],
    );
    // Two rolled into each other.
    marble(
        &mut world,
        &mut bodies,
        "striker_a",
        [-0.7, r, -0.4],
        [0.5, 0.0, 0.0],
    );
    marble(
        &mut world,
        &mut bodies,
        "striker_b",
        [-0.1, r, -0.4],
        [-0.3, 0.0, 0.0],
    );
    // Dropped into the bowl, off its axis: rolls round it and settles.
    let c = BOWL_CENTRE;
    marble(
        &mut world,
        &mut bodies,
        "bowl_ball",
        [c[0] + 0.08, 0.33, c[2]],
        [0.0, 0.0, 0.25],
    );
    Scene { world, bodies }
}
