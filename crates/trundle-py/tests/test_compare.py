"""trundle.compare: the judge of `trundle compare` on numpy arrays — two takes of one preset
are a match, two different presets are not, the result equals the command's, bad input
raises ValueError."""

import json
import subprocess

import numpy as np
import pytest

import trundle

from conftest import trundle_bin


def test_two_takes_of_one_preset_match_and_another_preset_does_not():
    a = trundle.render("default", seconds=4.0, seed=1)
    b = trundle.render("default", seconds=4.0, seed=2)
    c = trundle.render("marble-on-glass", seconds=4.0, seed=1)
    same = trundle.compare(a, b, 48000)
    assert same["passed"], same
    other = trundle.compare(a, c, 48000)
    assert not other["passed"] and not other["spectrum"]["passed"], other
    for m in ("spectrum", "modulation", "texture", "kurtosis_ratio", "crest_db"):
        assert np.isfinite(other[m]["value"]) and other[m]["limit"] > 0


def test_mono_and_stereo_are_read_as_the_command_reads_files(tmp_path):
    # The command reads a file as its mono mix: the same numbers from the CLI on the f32
    # files as from the package on the arrays.
    exe = trundle_bin()
    for seed in ("1", "3"):
        subprocess.run(
            [exe, "render", "--seconds", "2", "--seed", seed, "--format", "f32",
             "--no-normalize", "--set", "limiter=off", "-o", str(tmp_path / f"s{seed}.wav")],
            check=True, capture_output=True,
        )
    out = subprocess.run(
        [exe, "compare", str(tmp_path / "s1.wav"), str(tmp_path / "s3.wav"), "--json"],
        check=True, capture_output=True, text=True,
    )
    cli = json.loads(out.stdout)
    off = {"limiter": "off"}
    a = trundle.render("default", seconds=2.0, seed=1, params=off)
    b = trundle.render("default", seconds=2.0, seed=3, params=off)
    py = trundle.compare(a, b, 48000)
    for m in ("spectrum", "modulation", "texture"):
        assert py[m]["value"] == pytest.approx(cli[m]["value"], rel=1e-6, abs=1e-9), m
    mono = trundle.compare(a.mean(axis=1), b.mean(axis=1), 48000)
    # a.mean in float32 rounds the mix (the package mixes in float64): 1e-6.
    assert mono["spectrum"]["value"] == pytest.approx(py["spectrum"]["value"], rel=1e-6)


def test_bad_input_raises_value_error():
    a = trundle.render("default", seconds=1.0, seed=1)
    with pytest.raises(ValueError):
        trundle.compare(a[:1000], a, 48000)
    with pytest.raises(ValueError):
        trundle.compare(np.zeros(48000), a, 48000)
    with pytest.raises(ValueError):
        trundle.compare(a, a, float("nan"))
    with pytest.raises(ValueError):
        trundle.compare(np.zeros((2, 2, 2)), a, 48000)
