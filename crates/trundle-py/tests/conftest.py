"""What the tests share: the `trundle` command they compare with, and its f32 WAV read back."""

import os
import pathlib
import struct
import subprocess

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]


def trundle_bin() -> pathlib.Path:
    """The `trundle` command: $TRUNDLE_BIN, else the workspace's release build, else its
    debug build. Missing, the comparison FAILS (build it: cargo build --release -p
    trundle-cli); it never skips."""
    given = os.environ.get("TRUNDLE_BIN")
    candidates = [pathlib.Path(given)] if given else [
        REPO / "target" / "release" / "trundle",
        REPO / "target" / "debug" / "trundle",
    ]
    for path in candidates:
        if path.is_file():
            return path
    pytest.fail(
        "the trundle command is needed to compare with: set TRUNDLE_BIN or run "
        "`cargo build --release -p trundle-cli` (looked for "
        + ", ".join(str(c) for c in candidates) + ")"
    )


def read_f32_wav(path: pathlib.Path) -> tuple:
    """A 32-bit float WAV's samples as a (frames, channels) float32 array, and its rate.

    Walks the RIFF chunks: `fmt ` must say IEEE float (format 3, or WAVE_FORMAT_EXTENSIBLE
    with the float sub-format), 32 bits; `data` is taken as it is, little-endian."""
    raw = path.read_bytes()
    assert raw[:4] == b"RIFF" and raw[8:12] == b"WAVE", f"{path}: not a RIFF/WAVE file"
    pos, fmt, data = 12, None, None
    while pos + 8 <= len(raw):
        chunk_id, size = raw[pos:pos + 4], struct.unpack_from("<I", raw, pos + 4)[0]
        body = raw[pos + 8:pos + 8 + size]
        if chunk_id == b"fmt ":
            fmt = body
        elif chunk_id == b"data":
            data = body
        pos += 8 + size + (size & 1)  # chunks are padded to an even length
    assert fmt is not None and data is not None, f"{path}: no fmt or data chunk"
    tag, channels, rate = struct.unpack_from("<HHI", fmt, 0)
    bits = struct.unpack_from("<H", fmt, 14)[0]
    if tag == 0xFFFE:  # WAVE_FORMAT_EXTENSIBLE: the sub-format GUID starts with the tag
        tag = struct.unpack_from("<H", fmt, 24)[0]
    assert (tag, bits) == (3, 32), f"{path}: format {tag}, {bits} bits, not 32-bit float"
    samples = np.frombuffer(data, dtype="<f4")
    return samples.reshape(-1, channels), rate


def cli_render(tmp_path: pathlib.Path, *args: str) -> tuple:
    """`trundle render ARGS --format f32` into a scratch file, read back."""
    out = tmp_path / "cli.wav"
    cmd = [str(trundle_bin()), "render", "-o", str(out), "--format", "f32", *args]
    done = subprocess.run(cmd, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(cmd)} failed: {done.stderr}"
    return read_f32_wav(out)
