#!/usr/bin/env python3
"""Trundle.vst3 in a second, independent host: Spotify's pedalboard (JUCE's VST3 hosting).

The CLAP host tests (tests/tests/*.rs) drive the plugin through clack-host; this script
loads the *VST3* bundle in a host that shares no code with nice-plug or clack and checks
what a user of any DAW relies on:

* it loads headless as an instrument, reports its latency (the limiter's look-ahead);
* MIDI balls (note on/off at several pitches and velocities) render finite audio with no
  subnormal sample, peaking at or below the limiter's ceiling (-1 dBFS, on by default);
* the output is stereo (left and right differ but correlate, their mid is not silent) and
  its RMS is in a plausible range; every ball is heard and gets louder with velocity; the
  notes are heard over a stopped transport, `run = always` rolls the main ball without them;
* driven +12 dB, the limiter holds -1 dBFS (and switched off, it does not); bypass is silent;
* rendering again after a reset gives the same samples (reset determinism), both through
  pedalboard's `reset=True` and an explicit `plugin.reset()`;
* a parameter set by name (`roughness`) changes the sound and reads back;
* a state round trip: `raw_state` saved from one instance and loaded into a fresh one
  gives that instance the same parameters and the same samples.

Run: python3 tests/vst3/test_pedalboard.py [path/to/Trundle.vst3]
(default: $TRUNDLE_VST3_BUNDLE, else target/bundled/Trundle.vst3 of this repository; build
it with `cargo xtask bundle trundle --release`). Plain asserts; exits non-zero on the first
failing check. pytest can run the same file (every check is a `test_*` function).
"""

import os
import sys
import time

import numpy as np
import pedalboard

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
FS = 48_000.0
DURATION = 3.0
BLOCK = 512
# The limiter's ceiling, -1 dBFS, plus float32 rounding.
CEILING = 10.0 ** (-1.0 / 20.0)
CEILING_TOL = 1e-6
# The limiter's look-ahead at 48 kHz (1.5 ms).
LATENCY_48K = 72
TINY = np.finfo(np.float32).tiny  # smallest normal float32


def bundle_path():
    if len(sys.argv) > 1 and not sys.argv[1].startswith("-"):
        return sys.argv[1]
    return os.environ.get(
        "TRUNDLE_VST3_BUNDLE", os.path.join(ROOT, "target", "bundled", "Trundle.vst3")
    )


def load():
    path = bundle_path()
    assert os.path.isdir(path), f"no VST3 bundle at {path} (cargo xtask bundle trundle --release)"
    return pedalboard.load_plugin(path)


def note_on(key, velocity, t):
    return (bytes([0x90, key, velocity]), t)


def note_off(key, t):
    return (bytes([0x80, key, 0]), t)


# Balls: (key, velocity, start s, stop s). Low notes are big balls, high notes small ones;
# the loud ones overlap so the limiter has something to do.
BALLS = [
    (36, 127, 0.10, 2.20),
    (48, 100, 0.30, 1.60),
    (60, 64, 0.50, 2.40),
    (67, 127, 0.55, 1.30),
    (72, 32, 0.80, 2.00),
    (84, 127, 1.00, 2.60),
    (96, 90, 1.20, 1.90),
]


def balls():
    events = []
    for key, velocity, start, stop in BALLS:
        events.append(note_on(key, velocity, start))
        events.append(note_off(key, stop))
    return sorted(events, key=lambda e: e[1])


def render(plugin, midi=None, reset=True):
    out = plugin(
        balls() if midi is None else midi,
        duration=DURATION,
        sample_rate=FS,
        num_channels=2,
        buffer_size=BLOCK,
        reset=reset,
    )
    assert out.shape == (2, int(DURATION * FS)), f"output shape {out.shape}"
    assert out.dtype == np.float32
    return out


def rms(x):
    return float(np.sqrt(np.mean(np.square(x.astype(np.float64)))))


def db(x):
    return 20.0 * np.log10(max(x, 1e-30))


_PLUGIN = None


def plugin():
    """One instance shared by the checks that leave it at its defaults."""
    global _PLUGIN
    if _PLUGIN is None:
        _PLUGIN = load()
    return _PLUGIN


def test_loads_as_an_instrument():
    p = plugin()
    assert p.is_instrument, "not an instrument"
    assert not p.is_effect
    assert p.name == "Trundle", p.name
    for key in ("roughness", "velocity", "limiter", "width", "seed"):
        assert key in p.parameters, f"no parameter {key!r}: {sorted(p.parameters)}"


def test_latency_is_the_limiters_look_ahead():
    p = plugin()
    render(p)  # pedalboard prepares the plugin (sample rate, block size) when it renders
    assert p.reported_latency_samples == LATENCY_48K, p.reported_latency_samples


def test_midi_balls_are_finite_normal_and_below_the_ceiling():
    out = render(plugin())
    assert np.all(np.isfinite(out)), "non-finite sample"
    subnormal = (out != 0.0) & (np.abs(out) < TINY)
    assert not subnormal.any(), f"{int(subnormal.sum())} subnormal samples"
    peak = float(np.max(np.abs(out)))
    print(f"    peak {db(peak):.2f} dBFS, RMS L {db(rms(out[0])):.1f} R {db(rms(out[1])):.1f} dBFS")
    assert peak <= CEILING + CEILING_TOL, f"peak {peak} ({db(peak):.3f} dBFS) above -1 dBFS"
    assert peak > 0.1, f"peak {peak}: the balls are barely audible"


def test_output_is_stereo_with_a_plausible_level():
    out = render(plugin())
    left, right = out[0].astype(np.float64), out[1].astype(np.float64)
    assert not np.array_equal(left, right), "left == right: mono output"
    corr = float(np.corrcoef(left, right)[0, 1])
    mid = 0.5 * (left + right)
    print(f"    L/R correlation {corr:.3f}, mid RMS {db(rms(mid)):.1f} dBFS")
    assert corr > 0.5, f"L/R correlation {corr}"
    assert rms(mid) > 10.0 ** (-50 / 20), f"mid RMS {db(rms(mid)):.1f} dBFS: silent"
    for name, ch in (("left", left), ("right", right)):
        level = db(rms(ch))
        assert -45.0 < level < -6.0, f"{name} RMS {level:.1f} dBFS outside (-45, -6)"


def test_the_notes_are_heard_and_run_always_rolls_without_them():
    p = load()
    with_balls = render(p)
    # The plugin sees pedalboard's transport as stopped: with `run = with transport` (the
    # default) the main ball rests, so without notes there is nothing to hear.
    without = render(p, midi=[])
    print(f"    with the balls {db(rms(with_balls)):.1f} dBFS, without {db(rms(without)):.1f} dBFS")
    assert db(rms(with_balls)) - db(rms(without)) > 20.0, "the MIDI notes are not heard"
    p.run = "always"  # set by name, as text
    assert p.parameters["run"].raw_value == 1.0, p.parameters["run"].raw_value
    # reset=False: pedalboard resets an instrument by re-creating it and waiting (up to
    # 10 s) for a test note to be louder than its idle output, which a rolling ball never
    # lets happen; no reset is needed here.
    rolling = render(p, midi=[], reset=False)
    print(f"    run = always, no notes: {db(rms(rolling)):.1f} dBFS")
    assert db(rms(rolling)) > -40.0, "run = always: the main ball does not roll"


def test_every_ball_is_heard_and_velocity_sets_its_level():
    p = plugin()
    for key in (36, 60, 84, 96):
        levels = []
        for velocity in (20, 64, 127):
            out = render(p, midi=[note_on(key, velocity, 0.1), note_off(key, 1.5)])
            assert np.all(np.isfinite(out))
            levels.append(db(rms(out)))
        print(f"    key {key}: RMS at velocity 20/64/127 = " + " / ".join(f"{x:.1f}" for x in levels))
        assert levels[0] > -45.0, f"key {key} at velocity 20: {levels[0]:.1f} dBFS"
        assert levels[0] < levels[1] < levels[2], f"key {key}: not louder with velocity {levels}"


def test_the_limiter_holds_the_ceiling_when_driven():
    p = load()
    p.gain = 12.0  # +12 dB into the limiter
    driven = render(p)
    peak = float(np.max(np.abs(driven)))
    print(f"    gain +12 dB, limiter on: peak {db(peak):.3f} dBFS")
    assert peak <= CEILING + CEILING_TOL, f"peak {db(peak):.4f} dBFS above the ceiling"
    assert peak > CEILING * 10.0 ** (-0.5 / 20.0), "the drive did not reach the limiter"
    subnormal = (driven != 0.0) & (np.abs(driven) < TINY)
    assert not subnormal.any(), f"{int(subnormal.sum())} subnormal samples"
    p.limiter = False
    assert p.parameters["limiter"].raw_value == 0.0
    raw = render(p)
    print(f"    limiter off: peak {db(float(np.max(np.abs(raw)))):.2f} dBFS")
    assert float(np.max(np.abs(raw))) > CEILING * 1.2, "limiter off but the peak is held"


def test_bypass_is_silent():
    p = load()
    p.bypass = True
    out = render(p, reset=False)  # (a reset would wait 10 s for a test note: see above)
    assert not np.any(out), f"bypassed output peaks at {np.max(np.abs(out))}"


def test_render_after_reset_is_identical():
    # pedalboard resets an instrument by re-creating it from its saved state, playing a
    # warm-up note (middle C) into it and then resetting and re-activating it: identical
    # renders mean that reset/activation puts the voice back in its exact initial state.
    p = plugin()
    first = render(p)
    more = render(p, reset=False)  # carries on from where the first render stopped
    assert not np.array_equal(first, more), "a continued render repeated the first"
    second = render(p)
    assert np.array_equal(first, second), (
        f"renders after a reset differ: max |diff| {np.max(np.abs(first - second))}"
    )
    p.reset()
    third = render(p, reset=False)
    assert np.array_equal(first, third), (
        f"render after plugin.reset() differs: max |diff| {np.max(np.abs(first - third))}"
    )


def test_a_parameter_set_by_name_changes_the_sound():
    p = load()
    before = render(p)
    default = p.roughness
    p.roughness = 90  # by name, in the plugin's unit (%)
    assert p.roughness == 90, p.roughness
    # pedalboard picks the normalized value whose text reads "90 %" (0.895 here).
    assert abs(p.parameters["roughness"].raw_value - 0.9) < 0.01
    after = render(p)
    assert np.all(np.isfinite(after))
    diff = rms(after - before) / rms(before)
    print(f"    roughness {default} -> 90 %: relative RMS difference {diff:.3f}")
    assert diff > 0.05, f"roughness barely changed the sound ({diff})"


def test_state_round_trip():
    a = load()
    a.parameters["roughness"].raw_value = 0.8
    a.parameters["seed"].raw_value = a.parameters["seed"].raw_value + 0.01
    a.parameters["width"].raw_value = 0.3
    want = {k: a.parameters[k].raw_value for k in ("roughness", "seed", "width")}
    state = a.raw_state
    assert isinstance(state, bytes) and len(state) > 0
    out_a = render(a)

    b = load()
    default_out = render(b)
    assert not np.array_equal(out_a, default_out), "the changed parameters changed nothing"
    b.raw_state = state
    got = {k: b.parameters[k].raw_value for k in want}
    for k in want:
        assert abs(got[k] - want[k]) < 1e-6, f"{k}: restored {got[k]}, saved {want[k]}"
    out_b = render(b)
    assert np.array_equal(out_a, out_b), (
        f"restored instance differs: max |diff| {np.max(np.abs(out_a - out_b))}"
    )


def main():
    print(f"pedalboard {pedalboard.__version__}, numpy {np.__version__}, bundle {bundle_path()}")
    tests = [(n, f) for n, f in globals().items() if n.startswith("test_") and callable(f)]
    started = time.monotonic()
    for name, test in tests:
        t = time.monotonic()
        print(f"  {name} ...", flush=True)
        test()
        print(f"  {name} ok ({time.monotonic() - t:.1f} s)", flush=True)
    print(f"{len(tests)} checks passed in {time.monotonic() - started:.1f} s")


if __name__ == "__main__":
    main()
