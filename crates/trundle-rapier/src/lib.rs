//! # trundle-rapier — a real physics engine drives Trundle
//!
//! Balls dropped on a table and into a bowl in Rapier (`rapier3d`): they bounce, roll,
//! collide and settle. After every physics step (60 Hz, fixed) each pair's contact goes into
//! the runtime's contact stream ([`trundle_runtime::ContactStream`]), which renders that
//! step's 800 frames at 48 kHz, the image following each ball; the stream's events make a
//! JSON log of voices ([`log`]).

pub mod contacts;
pub mod log;
pub mod scene;

use trundle_runtime::{ContactStream, Listener, StreamSettings};

/// Physics steps per second (fixed).
pub const FRAME_RATE_HZ: f64 = 60.0;
/// The render's sample rate (Hz).
pub const SAMPLE_RATE_HZ: f64 = 48_000.0;

/// A rendered scene.
pub struct Rendered {
    /// Left channel.
    pub left: Vec<f32>,
    /// Right channel.
    pub right: Vec<f32>,
    /// The voice log.
    pub log: log::Log,
}

/// Run the scene for `seconds` with the stream's `seed`.
pub fn run(seconds: f64, seed: u64) -> Result<Rendered, String> {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= 600.0) {
        return Err(format!("--seconds must be in (0, 600], got {seconds}"));
    }
    let mut scene = scene::build();
    scene.world.integration_parameters.dt = (1.0 / FRAME_RATE_HZ) as f32;
    let settings = StreamSettings {
        sample_rate_hz: SAMPLE_RATE_HZ,
        frame_rate_hz: FRAME_RATE_HZ,
        seed,
        // Strikes a little under the runtime's default: five marbles land in the first
        // quarter second, and the sum must stay clear of the never-clip guard.
        impact_gain: 0.06,
        // In front of the table, 60 cm above it, 1.5 m back; right = +x.
        listener: Listener {
            position_m: [0.0, 0.6, 1.5],
            right: [1.0, 0.0, 0.0],
            reference_distance_m: 1.0,
        },
        ..StreamSettings::default()
    };
    let mapping = settings.mapping;
    let mut stream =
        ContactStream::new(settings, &scene::materials()).map_err(|e| e.to_string())?;
    let steps = (seconds * FRAME_RATE_HZ).round() as usize;
    let per_step = (SAMPLE_RATE_HZ / FRAME_RATE_HZ) as usize;
    let mut out = Rendered {
        left: Vec::with_capacity(steps * per_step),
        right: Vec::with_capacity(steps * per_step),
        log: log::Log::default(),
    };
    let (mut l, mut r) = (vec![0f32; per_step], vec![0f32; per_step]);
    let (mut before, mut frame) = (Vec::new(), Vec::new());
    for step in 0..steps {
        contacts::velocities(&scene, &mut before);
        scene.world.step();
        contacts::contacts(&scene, &before, &mut frame);
        stream.update(&frame).map_err(|e| e.to_string())?;
        stream.render(&mut l, &mut r).map_err(|e| e.to_string())?;
        out.left.extend_from_slice(&l);
        out.right.extend_from_slice(&r);
        let time_s = step as f64 / FRAME_RATE_HZ;
        let log = &mut out.log;
        let scene = &scene;
        let frame = &frame;
        stream.drain_events(|e| {
            let name = |body: u64| {
                scene
                    .bodies
                    .iter()
                    .find(|b| u64::from(b.handle.into_raw_parts().0) == body)
                    .map_or("?", |b| b.name)
                    .to_string()
            };
            let contact = frame.iter().find(|c| c.pair == e.pair);
            let touching = contact.map_or("?".to_string(), |c| {
                let other = scene
                    .bodies
                    .iter()
                    .find(|b| b.material == c.materials[1] && b.radius_m.is_none());
                match other {
                    Some(b) => b.name.to_string(),
                    None => "marble".to_string(),
                }
            });
            let motion = contact.map_or(trundle_runtime::ContactKind::Roll, |c| mapping.motion(c));
            log.add(e, time_s, (name(e.body), touching), motion);
        });
    }
    Ok(out)
}
