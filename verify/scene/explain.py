"""``chaplygin run --explain``: what a run of a scene would do, without running it."""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

from ...derive.systems import SYSTEMS
from .registry import needs_trajectory, requested
from .resolution import decimal_text

if TYPE_CHECKING:
    from .resolution import Resolved
    from .schema import Scene

__all__ = ["explain_text", "rhs_operation_count"]


def rhs_operation_count(code: Any) -> int:
    """Arithmetic operations (binary, unary, calls) in the generated numpy right-hand side.

    Parameters
    ----------
    code : ModelCode

    Returns
    -------
    int
    """
    import ast
    import inspect

    tree = ast.parse(inspect.getsource(code.numpy.rhs))
    count = 0
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp | ast.UnaryOp):
            count += 1
        elif isinstance(node, ast.Call) and not (
            isinstance(node.func, ast.Attribute)
            and node.func.attr in ("zeros", "shape", "result_type")
        ):
            count += 1
    return count


def _largest_variant(system: str) -> Any:
    """The largest effect combination shipped in ``generated/``, or None (a described
    system ships none)."""
    from ...numerics.code import load_model_code

    variants = SYSTEMS[system].variants
    if not variants:
        return None
    biggest = max(variants, key=lambda v: (len(v), v))
    return load_model_code(system, biggest)


def explain_text(scene: Scene, res: Resolved) -> str:
    """What a run of ``scene`` (resolved as ``res``) would do, as text (``--explain``).

    Parameters
    ----------
    scene : Scene
    res : Resolved

    Returns
    -------
    str
    """
    from ...numerics.code import generated_manifest
    from ..cli_common import printable

    code = res.code
    title = printable(scene.title or scene.source or "(untitled)", keep="")
    lines = [f"scene: {title}", f"model: {code.name}"]
    lines.append("effects:")
    if not res.effects:
        lines.append("  none (the bare system)")
    for e, why in res.effects.items():
        lines.append(f"  {e}: {why}")
    lines.append(f"states ({len(code.state)}): {', '.join(code.state)}")
    lines.append(
        "parameters: "
        + ", ".join(f"{k} = {decimal_text(v, res.digits)}" for k, v in res.params.items())
    )
    lines.append(f"initial state ({res.how}):")
    lines.extend(f"  {k} = {v}" for k, v in res.state_by_name().items())
    for name, r in res.residuals.items():
        lines.append(f"  residual of {name}: {r:.3e}")
    big = _largest_variant(scene.system)
    ops = rhs_operation_count(code)
    if big is None:
        lines.append(f"right-hand side: {ops} operations ({len(code.state)} states)")
    else:
        lines.append(
            f"right-hand side: {ops} operations ({len(code.state)} states) against "
            f"{rhs_operation_count(big)} ({len(big.state)} states) for {big.name}, the largest "
            "effect combination in generated/"
        )
    manifest = generated_manifest()
    method = scene.run_options.method or "taylor"
    if code.name in manifest:
        files = manifest[code.name]["files"]
        if method == "taylor":
            which = _taylor_files(files, scene.run_options.precision)
        else:
            which = f"{files['c']} (compiled on first use, cached) or {files['numpy']}"
        code_line = f"code: generated/{which}"
    else:
        code_line = f"code: {code.note}"
    if needs_trajectory(scene):
        lines.append(f"{code_line}; trajectory method {method}")
    else:
        lines.append(code_line)
        lines.append("trajectory: none (the outputs are analyses; add [outputs.trajectory])")
    for key, (analysis, _) in requested(scene.outputs).items():
        lines.append(f"analysis {key}: {analysis.description}")
    return "\n".join(lines)


def _taylor_files(files: Mapping[str, str], precision) -> str:
    """Which generated Taylor source runs at ``precision`` (what --explain names)."""
    from ...numerics.inputs import Precision

    prec = Precision(precision)
    fallback = f"; generated/{files['taylor_py']} without a compiler)"
    if prec.is_double:
        what = ("double; the coefficients written out for the run's orders, pairs of nodes "
                "in vectors of two doubles")
    elif prec.is_quad:
        what = "__float128"
    else:
        arithmetic = prec.arithmetic
        if arithmetic.name == "mpfr" and "taylor_mpfr" in files:
            return f"{files['taylor_mpfr']} (compiled Taylor integrator, MPFR" + fallback
        what = arithmetic.description if arithmetic.name != "mpfr" else "MPFR in Python"
    return f"{files['taylor_c']} (compiled Taylor integrator, {what}" + fallback
