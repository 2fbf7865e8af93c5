"""fq.wire: frames and results as the multipart messages of fqd's wire protocol (docs/PROTOCOL.md).

For code that moves the bytes itself (its own ZeroMQ sockets, a recording, a test); fq.Producer
and fq.Consumer do the sockets too. Both directions are fq's C++ codec (fq_wire, fq_client),
so a frame is what fqpub sends and a result is decoded as fqsub decodes it: no Draco is
written or read in Python, and no draco_decoder runs.
"""
from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

from . import _fq


class Result:
    """One result fqd published for a frame.

    Attributes
    ----------
    positions : ndarray, shape (n, 3), float32
        The filtered positions in the frame's vertex order (the order the producer sent);
        empty for an ERROR result.
    labels : ndarray of uint32, shape (n,), or None
        One cluster label per vertex when the stream clusters, else None.
    faces : ndarray of int64, shape (m, 3), or None
        The triangles, for a stream that publishes the MESH form; None for the POSITIONS form
        (the default), whose faces are the frame's own.
    header : dict
        Every field of the ResultHeader: ``stream_id``, ``sequence``, ``status`` ('OK', 'LATE'
        or 'ERROR'), ``error``, ``latency_ms``, ``noise_estimate``, ``filter_noise``,
        ``cluster_count``, ``engine``, ``form``, the ``*_time_ns`` stamps, ``timings`` (stage
        name -> ms), ...
    """

    __slots__ = ("positions", "labels", "faces", "header")

    def __init__(self, positions: np.ndarray, labels: Optional[np.ndarray], faces: Optional[np.ndarray],
                 header: dict[str, Any]) -> None:
        self.positions = positions
        self.labels = labels
        self.faces = faces
        self.header = header

    @property
    def ok(self) -> bool:
        """Whether fqd filtered the frame (status OK or LATE); the reason is ``header['error']`` if not."""
        return self.header["status"] != "ERROR"

    def __repr__(self) -> str:
        h = self.header
        return (f"Result(stream={h['stream_id']!r}, sequence={h['sequence']}, status={h['status']}, "
                f"vertices={len(self.positions)}, latency_ms={h['latency_ms']:.1f})")


def _result(d: dict[str, Any]) -> Result:
    return Result(d["positions"], d["labels"], d["faces"], d["header"])


def encode_frame(V: Any, F: Any, stream: str, sequence: int, *, chunks: int = 0, position_bits: int = 16,
                 encode_speed: int = 10, compute: Optional[str] = None, **params: Any) -> list[bytes]:
    """One frame as the multipart message fqd ingests: [stream id][FrameHeader][Draco chunks].

    The frame is encoded as fqpub encodes it (fq_client's build_frame), with fqpub's defaults.

    Parameters
    ----------
    V : array_like, shape (n, 3)
        Vertex positions (any float or integer dtype). Every vertex must be used by a face.
    F : array_like, shape (m, 3)
        Triangles as vertex indices.
    stream : str
        Stream id: the topic of the results.
    sequence : int
        Frame number, echoed in the result's header.
    chunks : int, default 0
        Draco chunks (1..256), which fqd decodes at once; 0: one per 16,384 vertices, at most 16.
    position_bits : int, default 16
        Position quantization bits (1..30) on the frame's bounding box.
    encode_speed : int, default 10
        Draco speed 0..10 (10: fastest to encode and decode, largest).
    compute : {None, 'filter', 'cluster', 'filter_and_cluster'}
        What fqd computes for this frame; None: the stream's setting.
    **params
        Parameter overrides for this frame, by the names of fqctl and the wire (``sigma_s``,
        ``strength``, ``target_clusters``, ...); unset ones keep the stream's values.

    Returns
    -------
    list of bytes
        The message parts, to send as one multipart message on a PUSH socket.

    Raises
    ------
    ValueError
        Bad shapes or indices, a vertex used by no face, a bad option or parameter value.
    TypeError
        A keyword that is not a frame parameter.
    """
    return _fq.encode_frame(V, F, stream, int(sequence), int(chunks), int(position_bits), int(encode_speed),
                            compute or "", params)


def decode_result(parts: Sequence[bytes]) -> Result:
    """A result message fqd published ([stream id][ResultHeader][Draco chunks]) as arrays.

    The header is parsed and checked as fqsub checks it (wire version, chunk count, vertex
    count, labels), and the chunks decoded with fq's codec.

    Parameters
    ----------
    parts : sequence of bytes
        The message parts as received (e.g. ``socket.recv_multipart()``).

    Returns
    -------
    Result
        positions, labels, faces and header; an ERROR result has no positions.

    Raises
    ------
    ValueError
        Not a valid result message (too few parts, bad header, undecodable chunks).
    """
    return _result(_fq.decode_result([bytes(p) for p in parts]))


__all__ = ["Result", "decode_result", "encode_frame"]
