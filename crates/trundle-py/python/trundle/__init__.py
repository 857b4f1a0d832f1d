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

>>> import trundle
>>> x = trundle.render("marble-on-glass", seconds=1.0, seed=7, params={"size": 0.3})
>>> x.shape, x.dtype
((48000, 2), dtype('float32'))
"""

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

__all__ = [
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
