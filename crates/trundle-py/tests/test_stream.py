"""trundle.ContactStream: a physics engine's contacts in, one voice per touching pair out
(the runtime's contact stream through Python)."""

import numpy as np
import pytest

import trundle
from trundle import Contact, ContactStream, Listener, Material

RATE, FPS = 48000, 60
FRAME = RATE // FPS  # audio frames per physics frame


def rolling(pair=1, body=7, speed=0.4, radius=0.02, x=0.0, materials=(0, 0)):
    """A ball rolling without slip (r·ω = v) at `speed` m/s, resting its weight (a 50 g ball:
    0.5 N over a 60 Hz frame)."""
    return Contact(pair, body, tangential_speed_m_s=speed, angular_speed_rad_s=speed / radius,
                   radius_m=radius, point_m=(x, 0.0, 0.0), normal_impulse_n_s=0.5 / FPS,
                   materials=materials)


def play(stream, frames_of_contacts):
    """Update and render one physics frame at a time; the audio of all of them."""
    out = []
    for contacts in frames_of_contacts:
        stream.update(contacts)
        out.append(stream.render(FRAME))
    return np.concatenate(out)


def rms(x):
    return float(np.sqrt(np.mean(np.asarray(x, dtype=np.float64) ** 2)))


def test_a_ball_rolling_through_drop_outs_is_one_voice():
    # 3 s of rolling; the engine loses the contact for 2 frames every 15 (a common
    # narrow-phase hiccup). The runtime bridges drop-outs of up to 4 frames by default, so
    # this must be one voice, started once, never re-struck and never ended.
    s = ContactStream(materials=["wood"], sample_rate=RATE, frame_rate=FPS)
    frames = [[] if i % 15 in (13, 14) else [rolling()] for i in range(3 * FPS)]
    audio = play(s, frames)
    assert audio.shape == (3 * RATE, 2) and audio.dtype == np.float32
    assert np.isfinite(audio).all()
    events = s.events()
    assert s.voices_started == 1
    assert [e["kind"] for e in events].count("start") == 1
    assert not [e for e in events if e["kind"] in ("impact", "end")], events
    # It sounds all along: every 100 ms window after the first is well above silence
    # (−60 dBFS); a voice cut at each drop-out would leave near-silent windows.
    windows = audio[RATE // 10:].reshape(-1, RATE // 10, 2)
    assert min(rms(w) for w in windows) > 1e-3


def test_a_drop_strikes_then_rolls_then_rests():
    s = ContactStream(materials=[Material.metal(), Material.wood()], sample_rate=RATE,
                      frame_rate=FPS)
    drop = Contact(3, 9, normal_speed_m_s=1.5, radius_m=0.02, normal_impulse_n_s=0.02,
                   materials=(0, 1))
    frames = [[drop]] + [[rolling(pair=3, body=9, speed=0.3, materials=(0, 1))]] * 60
    at_rest = Contact(3, 9, radius_m=0.02, normal_impulse_n_s=0.5 / FPS, materials=(0, 1))
    frames += [[at_rest]] * 30
    audio = play(s, frames)
    kinds = [e["kind"] for e in s.events()]
    assert kinds[0] == "start" and "impact" in kinds, kinds
    assert kinds.index("impact") < kinds.index("end"), kinds
    assert s.voices_started == 1
    # The strike is the loudest moment: the first 50 ms peak above the rolling that follows.
    assert np.abs(audio[: RATE // 20]).max() > np.abs(audio[RATE // 2: RATE]).max()


def test_resting_frees_the_voice_with_reason_rest():
    s = ContactStream(sample_rate=RATE, frame_rate=FPS, hold={"rest_frames": 5})
    still = Contact(1, 1, radius_m=0.02, normal_impulse_n_s=0.5 / FPS)
    play(s, [[rolling()]] * 10 + [[still]] * 10)
    ends = [e for e in s.events() if e["kind"] == "end"]
    assert len(ends) == 1 and ends[0]["reason"] == "rest", ends


def test_same_frames_same_samples():
    frames = [[rolling(speed=0.2 + 0.01 * i)] for i in range(30)]
    a = play(ContactStream(seed=5), frames)
    b = play(ContactStream(seed=5), frames)
    assert np.array_equal(a, b)


def test_budget_merges_the_rest_into_the_crowd():
    # 12 balls, 4 voices of their own: the other 8 share the crowd voice.
    s = ContactStream(max_voices=4, sample_rate=RATE, frame_rate=FPS)
    balls = [rolling(pair=p, body=p, speed=0.1 + 0.03 * p, x=0.1 * p) for p in range(12)]
    audio = play(s, [balls] * 20)
    assert s.crowd_count == 8
    assert s.voices_sounding <= 5
    assert np.isfinite(audio).all() and rms(audio) > 1e-3


def test_the_image_follows_the_contact_point():
    # Default listener: 2 m in front of the origin, right = +x. A ball 1.5 m to the right
    # is louder in the right channel (constant-power pan), one to the left in the left.
    def channels(x):
        s = ContactStream(listener=Listener(position_m=(0, -2, 0), right=(1, 0, 0)))
        a = play(s, [[rolling(x=x)]] * 30)[RATE // 10:]
        return rms(a[:, 0]), rms(a[:, 1])
    left, right = channels(1.5)
    assert right > 2 * left
    left, right = channels(-1.5)
    assert left > 2 * right


@pytest.mark.parametrize(
    "contact, message",
    [
        (dict(normal_speed_m_s=float("nan")), "normal_speed_m_s"),
        (dict(radius_m=-0.01), "radius_m"),
        (dict(tangential_speed_m_s=-1.0), "tangential_speed_m_s"),
        (dict(materials=(0, 5)), "material"),
        (dict(point_m=(0.0, float("inf"), 0.0)), "point"),
    ],
)
def test_a_bad_frame_raises_and_changes_nothing(contact, message):
    good = ContactStream(seed=2)
    tried = ContactStream(seed=2)
    for s in (good, tried):
        s.update([rolling()])
    with pytest.raises(ValueError, match=message):
        tried.update([rolling(), Contact(2, 2, **contact)])
    assert np.array_equal(good.render(FRAME), tried.render(FRAME))
    assert tried.voices_started == good.voices_started == 1


def test_refused_calls():
    s = ContactStream(max_pairs=2)
    with pytest.raises(ValueError):
        s.update([rolling(pair=1), rolling(pair=1)])  # a pair given twice
    with pytest.raises(ValueError):
        s.update([rolling(pair=p) for p in range(3)])  # more than max_pairs
    with pytest.raises(ValueError):
        s.remove_pair(99)
    with pytest.raises(TypeError):
        s.update([{"pair": 1}])
    with pytest.raises(ValueError):
        Listener(right=(0, 0, 0))


@pytest.mark.parametrize(
    "kwargs",
    [
        dict(sample_rate=0),
        dict(frame_rate=float("nan")),
        dict(max_voices=0),
        dict(materials=[]),
        dict(materials=["cheese"]),
        dict(seed=-1),
        dict(params={"size": 7}),
        dict(hold={"dropout_frames": 10, "linger_frames": 2}),
        dict(hold={"no_such": 1}),
        dict(mapping={"rub_slip": -1.0}),
        dict(impact_gain=float("inf")),
    ],
)
def test_bad_settings_raise_value_error(kwargs):
    with pytest.raises(ValueError):
        ContactStream(**kwargs)


def test_material_checks_its_values():
    assert "shell" in repr(Material.glass())
    with pytest.raises(ValueError):
        Material(object_size_m=-1.0)
    with pytest.raises(ValueError, match="shape"):
        Material(shape="cube")
