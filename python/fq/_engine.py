"""fq.filter, fq.cluster and fq.engine_name.

The parameter keywords of filter and cluster are not listed here: the compiled module gives
them, one per member of fq's C++ parameter structs (python/keywords.cpp), with the structs'
defaults, and `_with_keywords` turns them into each function's signature and the
Parameters section of its docstring. A new parameter in C++ is a new keyword here.
"""
from __future__ import annotations

import inspect
import textwrap
from typing import Any, Callable, Literal

import numpy as np
from numpy.typing import NDArray

from . import _fq
from .mesh import as_mesh, is_mesh, moved_like

# The keywords every engine call takes besides the parameters, in the rows' form.
_ENGINE_ROWS = [
    ("engine", "str", "auto", ["auto", "cpu", "cuda"],
     "'auto' (CUDA when the build has it and a GPU is present), 'cpu' or 'cuda'."),
    ("threads", "int", 0, None, "CPU engine threads; 0 uses every hardware thread."),
]

_MESH_PARAMETERS = """\
V : array_like of shape (n, 3), or a mesh
    Vertex positions (any float or integer dtype), or an fq.Mesh, open3d TriangleMesh or
    trimesh.Trimesh (then F is left out).
F : array_like of shape (m, 3), optional
    Triangles as vertex indices in 0..n-1 (integers); needed when V is an array."""


_TYPES = {"float": float, "int": int, "bool": bool, "str": str}


# The Raises section of both engine calls.
_ENGINE_RAISES = """\
Raises
------
TypeError
    An unknown keyword, a value of the wrong type, or more than two positional arguments.
ValueError
    A bad shape, dtype or index, an empty mesh, or a parameter out of its range.
RuntimeError
    The engine asked for is not available (``engine='cuda'`` without a GPU).
KeyboardInterrupt
    Ctrl-C during the run: the engine stops at its next check and nothing is returned."""


def _annotation(kind: str, choices: list[str] | None) -> Any:
    """The keyword's type as an object, so that help() shows ``sigma_r: float = 0.7``."""
    return Literal[tuple(choices)] if choices else _TYPES[kind]


def _param_names() -> list[tuple[str, str, list[str]]]:
    """The rows of fq's parameter table as (name, Python keyword, surfaces), surfaces among
    "fqfilter", "toml", "wire", "filter", "cluster", "Stream", "report"; tests walk it."""
    return [(name, keyword, list(surfaces)) for name, keyword, surfaces in _fq.param_rows()]


def _describe(name: str, kind: str, default: Any, choices: list[str] | None, help_text: str) -> str:
    shown = "{" + ", ".join(repr(c) for c in choices) + "}" if choices else kind
    return f"{name} : {shown}, default {default!r}\n" + textwrap.fill(
        help_text, 92, initial_indent="    ", subsequent_indent="    ")


# fq.filter's own keyword, in the rows' form.
_INFO_ROW = ("return_info", "bool", False, None,
             "Also return a dict of what was done: ``noise_estimate`` (the noise read from the mesh, mean "
             "edges), ``noise_residual`` (the residual it was read from: the rest was taken for the "
             "surface's detail), ``noise_directional``, ``noise_direction`` and ``noise_alignment`` (noise "
             "along one direction the mesh shares, as a range scan's line of sight: mean edges, 0 where none "
             "stands out; its unit direction; the RMS of n.d), ``filtered_for`` (the noise the strengths came "
             "from; these six None for modes other than qf+), ``moved_mean``, ``moved_p99`` and ``moved_max`` (how far "
             "vertices moved, mean edges), ``welded_vertices`` (coincident vertices filtered as one with their "
             "twins: seams) and ``mean_edge`` (input units).")


def _with_keywords(function_name: str, returns: str,
                   own: tuple[tuple[Any, ...], ...] = ()) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Gives the decorated ``f(V, F=None, **keywords)`` the keywords of the compiled
    module's rows for `function_name`: a signature (what help() and IDEs show), the
    Parameters section of its docstring ({parameters} in it; {raises} is the Raises section),
    and the defaults that `_split` checks keywords against."""
    rows = list(_fq.keywords(function_name)) + _ENGINE_ROWS + list(own)

    def decorate(f: Callable[..., Any]) -> Callable[..., Any]:
        P = inspect.Parameter
        f.__signature__ = inspect.Signature(  # type: ignore[attr-defined]
            [P("V", P.POSITIONAL_OR_KEYWORD, annotation="Union[ArrayLike, MeshLike]"),
             P("F", P.POSITIONAL_OR_KEYWORD, default=None, annotation="Optional[ArrayLike]")]
            + [P(r[0], P.KEYWORD_ONLY, default=r[2], annotation=_annotation(r[1], r[3])) for r in rows],
            return_annotation=returns)
        parameters = "\n".join([_MESH_PARAMETERS] + [_describe(*r) for r in rows])
        f.__doc__ = inspect.cleandoc(f.__doc__ or "").replace("{parameters}", parameters).replace(
            "{raises}", _ENGINE_RAISES)
        f.defaults = {r[0]: r[2] for r in rows}  # type: ignore[attr-defined]
        return f

    return decorate


def _engine_keywords(function_name: str, keywords: dict[str, Any], defaults: dict[str, Any],
                     also: tuple[str, ...] = ()) -> tuple[str, int]:
    """Checks `keywords` against `defaults` (TypeError naming the first unknown one; `also`:
    the caller's own keywords, named in the message) and pops engine and threads from them."""
    unknown = sorted(set(keywords) - set(defaults))
    if unknown:
        raise TypeError(f"{function_name}() got an unexpected keyword argument '{unknown[0]}' "
                        f"(it takes {', '.join((*also, *defaults))})")
    return keywords.pop("engine", defaults["engine"]), keywords.pop("threads", defaults["threads"])


def _split(function_name: str, V: Any, F: Any, keywords: dict[str, Any],
           defaults: dict[str, Any]) -> tuple[Any, Any, dict[str, Any], str, int]:
    """(V, F, parameter keywords, engine, threads) of a call; V, F taken from a mesh."""
    engine, threads = _engine_keywords(function_name, keywords, defaults)
    if F is None:
        if not is_mesh(V):
            raise TypeError(f"{function_name}() needs F with an array V (or a mesh as V)")
        mesh = as_mesh(V)
        V, F = mesh.vertices, mesh.faces
    elif is_mesh(V):
        raise TypeError(f"{function_name}() takes F only with an array V, not with a mesh")
    if not isinstance(engine, str):
        raise TypeError(f"engine must be a string, got {type(engine).__name__}")
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)):
        raise TypeError(f"threads must be an integer, got {type(threads).__name__}")
    return V, F, keywords, engine, int(threads)


@_with_keywords("filter", "Union[NDArray[np.floating], MeshLike, tuple[Any, dict[str, Any]]]", (_INFO_ROW,))
def filter(V: Any, F: Any = None, **keywords: Any) -> Any:  # noqa: A001 (fq.filter is the name users know)
    """Smooth a mesh with filtered quadrics: new vertex positions, the triangles unchanged.

    The defaults are fqfilter's: the same input and keywords give bit-identical positions
    to ``fqfilter`` with the same options on the same engine. Every sigma is in mean edge
    lengths of the mesh. The engine runs without the GIL; Ctrl-C stops it.

    Parameters
    ----------
    {parameters}

    Returns
    -------
    numpy.ndarray of shape (n, 3), or a mesh
        For arrays: the new positions, float64 when V is float64, else float32. For a mesh:
        a new mesh of the same kind with the new positions, its normals those of the new
        surface (never the input's) and its other attributes kept. The input is never modified.
        With ``return_info=True``: a tuple (that result, the info dict).

    {raises}
    """
    mesh = V if F is None else None
    return_info = keywords.pop("return_info", False)
    if not isinstance(return_info, bool):
        raise TypeError(f"return_info must be a bool, got {type(return_info).__name__}")
    V, F, params, engine, threads = _split("filter", V, F, keywords, filter.defaults)  # type: ignore[attr-defined]
    out = _fq.filter(V, F, params, engine, threads, return_info)
    positions, info = out if return_info else (out, None)
    result = positions if mesh is None else moved_like(mesh, positions)
    return (result, info) if return_info else result


@_with_keywords("cluster", "NDArray[np.uint32]")
def cluster(V: Any, F: Any = None, **keywords: Any) -> NDArray[np.uint32]:
    """Cluster a mesh with filtered quadrics: one label per vertex, positions unchanged.

    As ``fqfilter --no-filter``: the same input and keywords give the same labels. Every
    sigma is in mean edge lengths of the mesh. The engine runs without the GIL; Ctrl-C
    stops it.

    Parameters
    ----------
    {parameters}

    Returns
    -------
    numpy.ndarray of shape (n,)
        uint32 labels; every label in 0..k-1 is used, k the number of clusters.

    {raises}
    """
    V, F, params, engine, threads = _split("cluster", V, F, keywords, cluster.defaults)  # type: ignore[attr-defined]
    return _fq.cluster(V, F, params, engine, threads)


def engine_name(engine: str = "auto", threads: int = 0) -> str:
    """The engine that ``engine`` selects on this machine.

    Parameters
    ----------
    engine : {'auto', 'cpu', 'cuda'}, default 'auto'
        As for filter and cluster.
    threads : int, default 0
        CPU engine threads; 0 uses every hardware thread.

    Returns
    -------
    str
        ``'cpu'`` or ``'cuda:<device name>'``.

    Raises
    ------
    ValueError
        An unknown engine name or a negative thread count.
    RuntimeError
        ``engine='cuda'`` where no GPU or no CUDA build is present.
    """
    return _fq.engine_name(engine, threads)


