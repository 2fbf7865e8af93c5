"""fq.Stream: one stream's frames filtered in order, each with the stream's last result."""
from __future__ import annotations

from typing import Any

from . import _fq
from ._engine import _engine_keywords, _split, filter as _filter
from .mesh import moved_like


class Stream:
    """Frames of one capture stream, filtered in order with qf+ and the stream's history.

    When a frame keeps the last frame's vertex count and triangles (a tracked template, a
    keyframe run), its input is averaged with the stream's last averaged input through the
    vertex ids, once the ids are seen to follow a smooth motion, and then filtered (track
    ``'ids'``). Otherwise each frame's result is pulled along the normal towards the stream's
    last result where the surface held still, once the motion between the frames is taken out
    (track ``'space'``): such frames need not share vertex ids or triangles, a frame finds its
    prior in space. Either way static and slowly moving parts average their noise over time and
    flicker less, while parts that moved are left to the frame (docs/ALGORITHM.md, "Temporal
    filtering"). This is what ``fqfilter --sequence`` and an fqd stream with ``temporal`` do.

    Parameters
    ----------
    temporal : float, default 0.75
        How far a vertex may be pulled to the last result's surface, in [0, 1]; 0 filters
        each frame alone.
    **keywords
        fq.filter's keywords (``engine``, ``threads``, ``known_noise``, ``strength``, ...);
        ``mode`` must stay 'qf+'.

    Examples
    --------
    >>> stream = fq.Stream()
    >>> smoothed = [stream.filter(V, F) for V, F in frames]   # in capture order
    """

    def __init__(self, temporal: float = 0.75, **keywords: Any) -> None:
        if isinstance(temporal, bool) or not isinstance(temporal, (int, float)):
            raise TypeError(f"temporal must be a number, got {type(temporal).__name__}")
        engine, threads = _engine_keywords("Stream", keywords, _filter.defaults,  # type: ignore[attr-defined]
                                           also=("temporal",))
        self._stream = _fq.Stream(keywords, float(temporal), engine, threads)

    def filter(self, V: Any, F: Any = None) -> Any:
        """The next frame, filtered: as fq.filter, with the stream's history.

        V, F as for fq.filter (arrays, or a mesh as V). Returns the new positions (or a new
        mesh of the same kind). Frames must come in capture order; a frame far from the last
        one (a scene cut) starts the history again and counts in ``resets``.
        """
        mesh = V if F is None else None
        V, F, _, _, _ = _split("Stream.filter", V, F, {}, {"engine": "auto", "threads": 0})
        positions = self._stream.filter(V, F)
        return positions if mesh is None else moved_like(mesh, positions)

    def reset(self) -> None:
        """Forgets the history: the next frame is filtered alone (a new take, a camera change)."""
        self._stream.reset()

    @property
    def frames(self) -> int:
        """Frames filtered since the last reset or scene cut."""
        return int(self._stream.frames)

    @property
    def resets(self) -> int:
        """Scene cuts seen: frames that found under half their vertices near the last result."""
        return int(self._stream.resets)

    @property
    def temporal(self) -> float:
        """The temporal strength this stream was made with."""
        return float(self._stream.temporal)

    @property
    def last(self) -> dict[str, Any]:
        """What the last frame's filter found: ``noise_estimate`` (mean edges), ``prior_coverage``
        (share of vertices near the last result), ``prior_share`` (mean pull towards it, or with
        track ``ids`` the mean weight of the last averaged input), ``history_reset`` (a scene
        cut), ``track`` (``'ids'``: the frame kept the last one's connectivity and its input was
        averaged through the vertex ids; ``'space'``: the result was pulled towards the last
        one; ``'none'``), ``ids_refused`` (same connectivity, but the ids did not follow a
        smooth motion: track ``space`` ran) and ``ids_wide`` (track ``ids``: the mean share of
        the motion's eight-ring estimate, near 1 where the motion is smooth, low where it bends;
        0 otherwise)."""
        return dict(self._stream.last)
