"""fq.Producer and fq.Consumer: a capture pipeline's frames to fqd and its results back."""
from __future__ import annotations

from typing import Any, Iterator, Optional, TypeVar

from . import _fq
from .wire import Result, _result

_Self = TypeVar("_Self", bound="_Socket")


class _Socket:
    """A `with` block closes the socket of a Producer or Consumer."""

    def close(self) -> None:
        raise NotImplementedError

    def __enter__(self: _Self) -> _Self:
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class Producer(_Socket):
    """Sends frames to fqd's ingest endpoint, as fqpub does (a ZeroMQ PUSH socket that connects).

    Frames are numbered 0, 1, 2, ... in the order they are sent. Frames sent while no fqd is
    connected wait in the socket's queue; closing waits up to 5 s for queued frames to leave.

    Parameters
    ----------
    endpoint : str
        fqd's ingest endpoint, e.g. ``'tcp://127.0.0.1:5555'``.
    stream : str
        Stream id: the topic of its results.
    chunks, position_bits, encode_speed, compute, **params
        How each frame is encoded and what fqd computes, as for `fq.wire.encode_frame`.
    server_key : str, optional
        fqd's CURVE public key (Z85 text or a key file from fqkeys), for an fqd with CURVE.
    key_file : str, optional
        This client's CURVE key pair file (fqkeys); needed with server_key.

    Examples
    --------
    >>> with fq.Producer("tcp://127.0.0.1:5555", "cam") as producer:
    ...     producer.send(V, F)
    """

    def __init__(self, endpoint: str, stream: str, *, chunks: int = 0, position_bits: int = 16,
                 encode_speed: int = 10, compute: Optional[str] = None, server_key: Optional[str] = None,
                 key_file: Optional[str] = None, **params: Any) -> None:
        self._producer = _fq.Producer(endpoint, stream, int(chunks), int(position_bits), int(encode_speed),
                                      compute or "", params, server_key or "", key_file or "")

    def send(self, V: Any, F: Any, timeout_s: Optional[float] = None) -> int:
        """Encodes and sends one frame; returns its sequence number.

        Parameters
        ----------
        V : array_like, shape (n, 3)
            Vertex positions.
        F : array_like, shape (m, 3)
            Triangles as vertex indices.
        timeout_s : float, optional
            How long to wait while the socket cannot take the frame (no fqd connected yet, or
            its queue full); None: as long as it takes (Ctrl-C interrupts).

        Raises
        ------
        ValueError
            Bad shapes or indices, or a closed producer.
        TimeoutError
            The frame could not be queued within timeout_s.
        """
        return int(self._producer.send(V, F, -1.0 if timeout_s is None else float(timeout_s)))

    @property
    def sequence(self) -> int:
        """The sequence number the next frame gets."""
        return int(self._producer.sequence)

    def close(self) -> None:
        """Closes the socket (after up to 5 s for queued frames)."""
        self._producer.close()


class Consumer(_Socket):
    """Receives fqd's results from its publish endpoint, as fqsub does (a ZeroMQ SUB socket).

    Results published before a consumer connects are not seen (publish/subscribe), so create
    it before the frames it should see are sent; the constructor waits up to
    ``connect_timeout_s`` for the connection. Iterating yields results until the timeout of
    `recv` (`iter_timeout_s`) passes without one.

    Parameters
    ----------
    endpoint : str
        fqd's publish endpoint, e.g. ``'tcp://127.0.0.1:5556'``.
    stream : str, optional
        The stream to receive (exactly this id); None: every stream.
    server_key, key_file : str, optional
        CURVE keys, as for `Producer`.
    connect_timeout_s : float, default 1.0
        How long the constructor waits for fqd (0: not at all).
    iter_timeout_s : float, optional
        Iteration stops after this long without a result; None: iterates until Ctrl-C.

    Examples
    --------
    >>> consumer = fq.Consumer("tcp://127.0.0.1:5556", "cam")
    >>> result = consumer.recv(timeout_s=5)     # a fq.wire.Result, or None
    """

    def __init__(self, endpoint: str, stream: Optional[str] = None, *, server_key: Optional[str] = None,
                 key_file: Optional[str] = None, connect_timeout_s: float = 1.0,
                 iter_timeout_s: Optional[float] = None) -> None:
        self._consumer = _fq.Consumer(endpoint, stream, server_key or "", key_file or "", float(connect_timeout_s))
        self._iter_timeout_s = iter_timeout_s

    def recv(self, timeout_s: Optional[float] = None) -> Optional[Result]:
        """The next result, decoded; None when none came within timeout_s.

        Waits without holding the GIL; Ctrl-C interrupts it (KeyboardInterrupt).

        Parameters
        ----------
        timeout_s : float, optional
            Seconds to wait; None: until a result comes.

        Raises
        ------
        ValueError
            The message is not a valid result (e.g. another wire version), or the consumer is closed.
        """
        d = self._consumer.recv(-1.0 if timeout_s is None else float(timeout_s))
        return None if d is None else _result(d)

    def __iter__(self) -> Iterator[Result]:
        while (result := self.recv(self._iter_timeout_s)) is not None:
            yield result

    def close(self) -> None:
        """Closes the socket."""
        self._consumer.close()
