"""Trundle for Python: rolling, rubbing and scratching synthesis as numpy arrays.

``render`` and ``Renderer`` play a preset exactly as the ``trundle render`` command does
(the same engine, the same seed, the same samples), returning float32 arrays of shape
``(frames, 2)`` (left, right). The level is the engine's own: nothing is normalized, and
the safety limiter runs only when the preset's ``limiter`` is on (every built-in preset
turns it on; pass ``params={"limiter": "off"}`` for the raw signal). Refused arguments
raise ``ValueError`` with the engine's reason.

``ContactStream`` is the game-side half: every physics frame, what the engine knows about
each touching pair (``Contact``: speeds, spin, radius, point, normal, impulse, materials)
goes in, and one continuous, positioned sound per pair comes out (impacts when bodies
strike, a roll while they roll, a rub while they slide), with a log of its voices.

``compare`` judges a sound against a recording by the four measures of ``trundle compare``
(long-term spectrum, modulation spectrum, texture statistics, impulsiveness), each with its
limit and verdict.

>>> import trundle
>>> x = trundle.render("marble-on-glass", seconds=1.0, seed=7, params={"size": 0.3})
>>> x.shape, x.dtype
((48000, 2), dtype('float32'))
"""

import numpy as _np

from trundle import _native
from trundle._native import (
    Contact,
    ContactStream,
    Listener,
    Material,
    Renderer,
    __version__,
    parameters,
    presets,
    render,
)



def compare(recording, candidate, recording_rate, candidate_rate=None):
    """Judge ``candidate`` against ``recording`` as ``trundle compare`` does.

    Both are arrays of samples, mono or shaped ``(frames, channels)`` (mixed to mono), of any
    float dtype; rates in Hz (``candidate_rate`` defaults to ``recording_rate``). Returns a
    dict: ``passed``, ``measures_passed``, ``loss`` and, for ``spectrum``, ``modulation``,
    ``texture``, ``kurtosis_ratio`` and ``crest_db``, a dict of ``value``, ``limit`` and
    ``passed``. Raises ``ValueError`` for a sound under 0.5 s, silent or non-finite.
    """
    return _native.compare(
        _np.asarray(recording, dtype=_np.float64),
        _np.asarray(candidate, dtype=_np.float64),
        float(recording_rate),
        None if candidate_rate is None else float(candidate_rate),
    )


__all__ = [
    "compare",
    "Contact",
    "ContactStream",
    "Listener",
    "Material",
    "Renderer",
    "__version__",
    "parameters",
    "presets",
    "render",
]
