//! Expression per ball: what the host's note events do to the MIDI balls.
//!
//! Every MIDI note is a ball ([`trundle_dsp::scene::balls`]) named as the host names the note (its
//! voice id, channel and key), so a gesture reaches the ball it belongs to:
//!
//! | host gesture | ball | law |
//! |---|---|---|
//! | CLAP/VST3 pressure, polyphonic aftertouch | contact load | force × (1 + p) |
//! | CLAP/VST3 brightness (MPE timbre) | roughness | ρ_scene + (b − ½) |
//! | CLAP/VST3 tuning (MPE per-note pitch bend) | speed | V · 2^(t/12) |
//! | CLAP/VST3 volume | loudness | force × g |
//! | CLAP/VST3 pan | where it rolls | x + q, towards a pickup |
//! | CLAP poly modulation of `velocity`, `roughness`, `size` | that control | + the offset |
//!
//! **MPE** reaches the balls as note expressions: hosts that translate MPE for a CLAP or VST3
//! instrument (Bitwig Studio does for CLAP plugins) turn each note's channel pressure, CC 74 and
//! pitch bend into that note's pressure, brightness and tuning expressions. Raw MPE channel
//! messages are not read: that needs nice-plug's MIDI-CC input, whose 2 080 hidden VST3
//! MIDI-mapping parameters made the plugin take 24 s to load in pedalboard (JUCE).
//!
//! **Poly modulation** (CLAP hosts that offer it): the host's offset is a normalized offset
//! of the knob; it is turned into the control's own units at the knob's current position
//! (`plain(n + offset) − plain(n)`) and added to the ball's value — its note's speed and
//! size, the scene's roughness — clamped to the control's range. A ball that ends is
//! reported to the host (CLAP note end) so it frees the modulation voice.
//!
//! Everything here maps one event to another without allocating (it runs in `process`).

use crate::params::{TableParam, TrundleParams};
use nice_plug::midi::{Channel, Key, VoiceID};
use nice_plug::prelude::*;
use trundle_dsp::scene::balls::{BallId, BallTarget, Expression};
use trundle_dsp::scene::events::VoiceEvent;
use trundle_dsp::ParamId;

/// Poly modulation id of `velocity`.
pub const POLY_VELOCITY: u32 = 0;
/// Poly modulation id of `roughness`.
pub const POLY_ROUGHNESS: u32 = 1;
/// Poly modulation id of `size`.
pub const POLY_SIZE: u32 = 2;

/// The poly modulation id of a table parameter, for the three a ball carries on its own.
pub fn poly_modulation_id(key: &str) -> Option<u32> {
    match key {
        "velocity" => Some(POLY_VELOCITY),
        "roughness" => Some(POLY_ROUGHNESS),
        "size" => Some(POLY_SIZE),
        _ => None,
    }
}

fn target(voice_id: VoiceID, channel: Channel, key: Key) -> BallTarget {
    BallTarget {
        voice_id: voice_id.id(),
        channel: channel.number(),
        key: key.number(),
    }
}

/// The offset, in the control's units, that a normalized poly-modulation offset means at the
/// knob's current position.
fn plain_offset(param: &TableParam, normalized_offset: f32) -> f64 {
    match param {
        TableParam::Float(p) => {
            let n = p.unmodulated_normalized_value();
            f64::from(p.preview_plain(n + normalized_offset)) - f64::from(p.preview_plain(n))
        }
        TableParam::Int(_) => 0.0,
    }
}

/// What a host note event does to the voice (`None`: nothing). Real-time safe.
pub fn voice_event<S>(ev: &NoteEvent<S>, params: &TrundleParams) -> Option<VoiceEvent> {
    let express = |t: BallTarget, e: Expression| {
        Some(VoiceEvent::Express {
            target: t,
            expression: e,
        })
    };
    match *ev {
        NoteEvent::NoteOn {
            voice_id,
            channel,
            key,
            velocity,
            ..
        } => Some(VoiceEvent::BallOn {
            id: BallId {
                voice_id: voice_id.id(),
                channel: channel.number().unwrap_or(0),
                key: key.number_or_middle_c(),
            },
            velocity: f64::from(velocity),
        }),
        NoteEvent::NoteOff {
            voice_id,
            channel,
            key,
            ..
        }
        | NoteEvent::Choke {
            voice_id,
            channel,
            key,
            ..
        } => Some(VoiceEvent::BallOff {
            target: target(voice_id, channel, key),
        }),
        NoteEvent::PolyPressure {
            voice_id,
            channel,
            key,
            pressure,
            ..
        } => express(
            target(voice_id, channel, key),
            Expression::Pressure(f64::from(pressure)),
        ),
        NoteEvent::PolyBrightness {
            voice_id,
            channel,
            key,
            brightness,
            ..
        } => express(
            target(voice_id, channel, key),
            Expression::Brightness(f64::from(brightness)),
        ),
        NoteEvent::PolyTuning {
            voice_id,
            channel,
            key,
            tuning,
            ..
        } => express(
            target(voice_id, channel, key),
            Expression::TuningSemitones(f64::from(tuning)),
        ),
        NoteEvent::PolyVolume {
            voice_id,
            channel,
            key,
            gain,
            ..
        } => express(
            target(voice_id, channel, key),
            Expression::Volume(f64::from(gain)),
        ),
        NoteEvent::PolyPan {
            voice_id,
            channel,
            key,
            pan,
            ..
        } => express(
            target(voice_id, channel, key),
            Expression::Pan(f64::from(pan)),
        ),
        NoteEvent::PolyModulation {
            voice_id,
            poly_modulation_id,
            normalized_offset,
            ..
        } => {
            let (id, make): (ParamId, fn(f64) -> Expression) = match poly_modulation_id {
                POLY_VELOCITY => (ParamId::Velocity, Expression::VelocityOffset),
                POLY_ROUGHNESS => (ParamId::Roughness, Expression::RoughnessOffset),
                POLY_SIZE => (ParamId::Size, Expression::SizeOffset),
                _ => return None,
            };
            express(
                BallTarget {
                    voice_id: Some(voice_id),
                    ..BallTarget::ALL
                },
                make(plain_offset(params.get(id), normalized_offset)),
            )
        }
        _ => None,
    }
}

/// The host event saying a ball has ended (CLAP note end), at sample `timing`.
pub fn ended_event<S>(id: BallId, timing: u32) -> NoteEvent<S> {
    NoteEvent::VoiceTerminated {
        timing,
        voice_id: id.voice_id.map_or(VoiceID::Wildcard, VoiceID::ID),
        channel: Channel::Number(id.channel),
        key: Key::Number(id.key),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ev(e: NoteEvent<()>) -> Option<VoiceEvent> {
        voice_event(&e, &TrundleParams::default())
    }

    #[test]
    fn notes_name_their_balls() {
        let on = ev(NoteEvent::NoteOn {
            timing: 0,
            voice_id: VoiceID::ID(7),
            channel: Channel::Number(3),
            key: Key::Number(62),
            velocity: 0.5,
        });
        assert_eq!(
            on,
            Some(VoiceEvent::BallOn {
                id: BallId {
                    voice_id: Some(7),
                    channel: 3,
                    key: 62
                },
                velocity: 0.5
            })
        );
        let off = ev(NoteEvent::NoteOff {
            timing: 0,
            voice_id: VoiceID::Wildcard,
            channel: Channel::Number(3),
            key: Key::Number(62),
            velocity: 0.0,
        });
        assert_eq!(
            off,
            Some(VoiceEvent::BallOff {
                target: BallTarget {
                    voice_id: None,
                    channel: Some(3),
                    key: Some(62)
                }
            })
        );
    }

    #[test]
    fn poly_modulation_is_an_offset_in_the_controls_units() {
        let p = TrundleParams::default();
        let e = voice_event::<()>(
            &NoteEvent::PolyModulation {
                timing: 0,
                voice_id: 9,
                poly_modulation_id: POLY_ROUGHNESS,
                normalized_offset: 0.25,
            },
            &p,
        );
        // Roughness is linear over 0…1: a quarter of the travel is 0.25.
        match e {
            Some(VoiceEvent::Express {
                target,
                expression: Expression::RoughnessOffset(d),
            }) => {
                assert_eq!(target.voice_id, Some(9));
                assert!((d - 0.25).abs() < 0.01, "{d}");
            }
            other => panic!("{other:?}"),
        }
        // The three poly-modulated controls have their ids, no other does.
        let ids: Vec<_> = trundle_dsp::PARAMS
            .iter()
            .filter_map(|s| poly_modulation_id(s.key))
            .collect();
        let mut ids = ids;
        ids.sort_unstable();
        assert_eq!(ids, vec![POLY_VELOCITY, POLY_ROUGHNESS, POLY_SIZE]);
    }
}
