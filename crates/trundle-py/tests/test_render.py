"""trundle.render and trundle.Renderer: shape, type, determinism, the command's samples,
and refused arguments."""

import json
import pathlib

import numpy as np
import pytest

import trundle
from conftest import REPO, cli_render


def test_shape_and_dtype():
    x = trundle.render(seconds=0.5)
    assert isinstance(x, np.ndarray)
    assert x.dtype == np.float32
    assert x.shape == (24000, 2)
    assert x.flags["C_CONTIGUOUS"]
    assert np.isfinite(x).all()
    # Sound, not silence: a rolling ball on a table at the engine's level is well above
    # -60 dBFS RMS (the default preset measures about -20 dBFS).
    assert np.sqrt(np.mean(x.astype(np.float64) ** 2)) > 1e-3


def test_frames_are_rounded_as_the_command_counts_them():
    assert trundle.render(seconds=0.01, sample_rate=44100).shape == (441, 2)
    assert trundle.render(seconds=1 / 3, sample_rate=8000).shape == (2667, 2)


def test_same_seed_same_samples_other_seed_other_samples():
    a = trundle.render(seconds=0.5, seed=3)
    b = trundle.render(seconds=0.5, seed=3)
    c = trundle.render(seconds=0.5, seed=4)
    assert np.array_equal(a, b)
    assert not np.array_equal(a, c)


def test_streaming_equals_one_call():
    # Blocks of awkward sizes (not multiples of the engine's 64-sample chunk) give the
    # same samples as one render: the engine does not depend on the block size.
    whole = trundle.render(seconds=0.25, seed=9)
    r = trundle.Renderer(seed=9)
    parts = [r.render(n) for n in (1, 63, 1000, 4097, 6839)]
    assert r.frames_done == 12000
    assert np.array_equal(np.concatenate(parts), whole)


@pytest.mark.parametrize(
    "preset, seconds, seed",
    [("default", 2.0, 1), ("marble-on-glass", 1.0, 7), ("dropped-steel-ball-on-wood-floor", 1.5, 42)],
)
def test_equals_the_command(tmp_path, preset, seconds, seed):
    # The same engine through the same render path: bit for bit. The brief allows 1e-6
    # where a boundary converts; nothing converts here (f32 in the engine, f32 in the WAV),
    # so the comparison is exact.
    ours = trundle.render(preset, seconds=seconds, seed=seed, params={"limiter": "off"})
    theirs, rate = cli_render(
        tmp_path, "--preset", preset, "--seconds", str(seconds), "--seed", str(seed),
        "--no-normalize", "--set", "limiter=off",
    )
    assert rate == 48000
    assert theirs.shape == ours.shape
    assert np.array_equal(ours, theirs), f"max difference {np.abs(ours - theirs).max()}"


def test_params_as_set_equal_the_command(tmp_path):
    # Numbers and text with units, in order, as --set takes them.
    params = {"limiter": "off", "size": 0.8, "roughness": "1", "velocity": "0.3 m/s"}
    ours = trundle.render(seconds=1.0, seed=5, sample_rate=44100, params=params)
    sets = [a for k, v in params.items() for a in ("--set", f"{k}={v}")]
    theirs, rate = cli_render(
        tmp_path, "--seconds", "1", "--seed", "5", "--sample-rate", "44100", "--no-normalize",
        *sets,
    )
    assert rate == 44100
    assert np.array_equal(ours, theirs), f"max difference {np.abs(ours - theirs).max()}"


def test_preset_as_json_text_and_as_file(tmp_path):
    text = (REPO / "presets" / "marble-on-glass.json").read_text()
    by_name = trundle.render("marble-on-glass", seconds=0.2)
    assert np.array_equal(trundle.render(text, seconds=0.2), by_name)
    path = tmp_path / "mine.json"
    path.write_text(text)
    assert np.array_equal(trundle.render(str(path), seconds=0.2), by_name)
    assert np.array_equal(trundle.render(path, seconds=0.2), by_name)  # os.PathLike


def test_limiter_on_keeps_the_peak_under_full_scale():
    # A loud scene behind the preset's limiter (-1 dBFS ceiling) never reaches full scale.
    x = trundle.render("bearings-tumbling-in-a-drum", seconds=1.0, params={"gain_db": "12 dB"})
    assert np.abs(x).max() <= 10 ** (-1 / 20) + 1e-6


def test_set_between_blocks_changes_the_sound():
    a = trundle.Renderer(seed=2)
    b = trundle.Renderer(seed=2)
    assert np.array_equal(a.render(4800), b.render(4800))
    b.set("size", 0.9)
    assert b.get("size") == 0.9
    assert not np.array_equal(a.render(4800), b.render(4800))


def test_tables():
    names = trundle.presets()
    assert "default" in names and "marble-on-glass" in names
    keys = {p["key"]: p for p in trundle.parameters()}
    assert keys["limiter"]["kind"] == "choice" and "off" in keys["limiter"]["choices"]
    assert keys["size"]["min"] <= keys["size"]["default"] <= keys["size"]["max"]
    json.dumps(trundle.parameters())  # plain Python values


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"preset": "no-such-preset"}, "no-such-preset"),
        ({"preset": "{not json"}, "preset"),
        ({"preset": "/no/such/file.json"}, "file.json"),
        ({"seconds": 0.0}, "seconds"),
        ({"seconds": float("nan")}, "seconds"),
        ({"seconds": -1.0}, "seconds"),
        ({"seconds": 1e-6}, "shorter than one frame"),
        ({"sample_rate": 100}, "sample rate"),
        ({"sample_rate": float("inf")}, "sample rate"),
        ({"seed": -1}, "seed"),
        ({"seed": 1 << 30}, "seed"),
        ({"params": {"no_such_key": 1}}, "no_such_key"),
        ({"params": {"size": 99.0}}, "size"),
        ({"params": {"size": float("nan")}}, "size"),
        ({"params": {"limiter": "sideways"}}, "sideways"),
        ({"params": {"seed": 3}}, "seed argument"),
    ],
)
def test_bad_input_raises_value_error(kwargs, message):
    with pytest.raises(ValueError, match=message):
        trundle.render(**{"seconds": 0.1, **kwargs})


@pytest.mark.parametrize("params", [{1: 2}, {"size": [1]}, {"limiter": True}])
def test_wrong_types_raise_type_error(params):
    with pytest.raises(TypeError):
        trundle.render(seconds=0.1, params=params)


def test_refused_set_changes_nothing():
    a = trundle.Renderer(seed=2)
    b = trundle.Renderer(seed=2)
    with pytest.raises(ValueError):
        b.set("size", -5)
    assert b.get("size") == a.get("size")
    assert np.array_equal(a.render(2000), b.render(2000))
