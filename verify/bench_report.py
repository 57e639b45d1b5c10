"""The work-precision study as text: the markdown table of ``bench.md`` and the speed targets of
issue 5 §4 against heyoka (:func:`speed_targets`, :func:`target_ratios`)."""

from __future__ import annotations

import math

from .bench_problems import PROBLEMS

__all__ = ["EQUAL_ERROR_FACTOR", "render_markdown", "speed_targets", "target_ratios"]


# --------------------------------------------------------------------------- output


def _fmt(x, spec=".2e") -> str:
    if x is None:
        return "-"
    if isinstance(x, float) and not math.isfinite(x):
        return "inf" if x > 0 else "nan"
    return format(x, spec)


def render_markdown(study: dict) -> str:
    """The study as Markdown: one table per problem, rhs-call and compile times, ratios.

    Parameters
    ----------
    study : dict
        The output of :func:`run_study` (or the JSON it was saved as).

    Returns
    -------
    str
        The Markdown document, ending with a newline.
    """
    rows = study["rows"]
    lines = ["# Work-precision study (chaplygin bench)", ""]
    if study.get("quick"):
        lines += ["**Quick run** (`--quick`): shortened spans and one run per row; see notes.", ""]
    for pname in dict.fromkeys(r["problem"] for r in rows):
        prob = PROBLEMS[pname]
        lines += [f"## {pname}: {prob.description}", ""]
        names = sorted({k for r in rows if r["problem"] == pname for k in r["drift"]})
        head = ["method", "rhs", "precision", "rtol", "T", "final error", *(
            f"drift {n}" for n in names), "median s", "runs", "steps", "rhs calls",
            "integrate() s (set-up + steps + evidence, ms)", "x heyoka",
            "propagate_until() s", "x heyoka", "note"]
        lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
        for r in rows:
            if r["problem"] != pname:
                continue
            cells = [r["method"], r["rhs"], r["precision"], _fmt(r["rtol"], ".0e"),
                     _fmt(r["T"], "g"), _fmt(r["error"]),
                     *(_fmt(r["drift"].get(n)) for n in names),
                     _fmt(r["median_s"], ".4g"), str(r["runs"]), _fmt(r["steps"], "d"),
                     _fmt(r.get("nfev"), "d"), _call_parts(r), _heyoka_ratio(r, rows),
                     _fmt(r.get("propagate_s"), ".4g"),
                     _heyoka_ratio(r, rows, "propagate_s"), r["note"]]
            lines.append("| " + " | ".join(cells) + " |")
        lines.append("")
    lines += ["## Right-hand side called from Python (seconds per evaluation)", ""]
    lines += [f"- {k}: {v * 1e9:.0f} ns" for k, v in study["rhs_call_s"].items()]
    lines += ["", "## Compile time (separate from the integration times above)", ""]
    lines += [
        f"- {k}: {v:.2f} s" if isinstance(v, float) else f"- {k}: {v}"
        for k, v in study["compile_s"].items()
    ]
    sections = (
        ("map_throughput", "BM20's stroboscopic map (us per forcing period per point)"),
        ("taylor_map_equal_accuracy", "BM20's map, the Taylor lanes against the DOP853 lanes at "
         "equal accuracy (us per forcing period per point; issue 26: Taylor at or below)"),
        ("lyapunov_throughput", "BM20's largest Lyapunov exponent (seconds per point; issue "
         "26's target <= 0.05 s, a 101 x 101 chart <= 15 min on 2 cores)"),
        ("regime_throughput", "BM20's regime of the attractor (seconds per point; the sweep's "
         "regime reducer, one point per call and a chunk in vector lanes)"),
        ("jacobian_throughput", "BM20's map Jacobian over one period (seconds per point; one "
         "call per point and many in vector lanes)"),
        ("verify_time", "The main job: chaplygin verify in its own process (issue 26: <= 60 s "
         "warm on 2 cores)"),
        ("enclosure_cost", "Proofs by computation: an enclosure beside the floating-point run "
         "(issue 27; the BM20 7-cycle proof <= 2 min on 2 cores)"),
    )  # fmt: skip
    for key, title in sections:
        values = study.get(key) or {}
        if values:
            lines += ["", f"## {title}", ""]
            lines += [f"- {k}: {v:.4g}" if isinstance(v, float) else f"- {k}: {v}"
                      for k, v in values.items()]  # fmt: skip
    ensemble = study.get("ensemble_throughput") or {}
    if ensemble:
        lines += ["", "## Many orbits at once (seconds per orbit; issue 26: integrate_many at or "
                  "below heyoka's batch mode)", ""]  # fmt: skip
        for key, row in ensemble.items():
            if isinstance(row, dict):
                cells = ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else f"{k} {v}"
                                  for k, v in row.items())  # fmt: skip
                lines.append(f"- {key}: {cells}")
            else:
                lines.append(f"- {key}: {row}")
    described = study.get("described_system_s") or {}
    if described:
        lines += ["", "## A described system: description -> equations -> discovery -> proofs "
                  "-> code (issue 24; target <= 60 s cold, <= 2 s warm)", ""]  # fmt: skip
        for run, stages in described.items():
            parts = ", ".join(
                f"{k} {v:.2f} s" if isinstance(v, float) else f"{k} {v}" for k, v in stages.items()
            )
            lines.append(f"- {run}: {parts}")
    lines += ["", "## Against heyoka at equal or better final error (issue 15, this run)", ""]
    lines += [f"- {t}" for t in speed_targets(study)] or ["- heyoka not installed"]
    lines += ["", "## Targets of issue 5 (ratios from this run)", ""]
    lines += [f"- {t}" for t in target_ratios(study)]
    return "\n".join(lines) + "\n"


def _call_parts(row: dict) -> str:
    """``call (setup + steps + evidence)`` of one of our rows, or ``-``."""
    if row.get("call_s") is None:
        return "-"
    ms = [1e3 * row[k] for k in ("setup_s", "median_s", "evidence_s")]
    return f"{row['call_s']:.4g} ({ms[0]:.2f} + {ms[1]:.2f} + {ms[2]:.2f})"


def _heyoka_peer(row: dict, rows: list[dict]) -> dict | None:
    """heyoka's row for one of ours: same problem, precision and span; in double the same
    tolerance, in the wider precisions heyoka's default (its epsilon)."""
    if row["method"] == "heyoka":
        return None
    label = {"quad": "quad (real128)"}.get(row["precision"], row["precision"])
    peers = [r for r in rows if r["method"] == "heyoka" and r["problem"] == row["problem"]
             and r["precision"] == label and r["T"] == row["T"] and r["median_s"]]
    same_tol = [r for r in peers if r["rtol"] == row["rtol"]]
    return (same_tol or ([] if row["precision"] == "double" else peers) or [None])[0]


def _heyoka_ratio(row: dict, rows: list[dict], key: str = "call_s") -> str:
    """Our ``integrate(...)`` call (``key="call_s"``) or ``Propagator.propagate_until``
    (``"propagate_s"``) over heyoka's ``propagate_until``, or ``-``."""
    peer = _heyoka_peer(row, rows)
    if row.get(key) is None or peer is None:
        return "-"
    return f"{row[key] / peer['median_s']:.2f}"


#: "Equal or better final error" (issue 15): at most this factor above heyoka's error (the
#: same method at the same tolerance gives errors that differ in their third digit).
EQUAL_ERROR_FACTOR = 1.25


def speed_targets(study: dict) -> list[str]:
    """Issue 15's comparison with heyoka, one sentence per problem and precision.

    For each heyoka row (double at its two tolerances, real128, 30, 50 and 100 digits) the
    fastest of our Taylor rows in the same precision and span whose final error is at most
    :data:`EQUAL_ERROR_FACTOR` times heyoka's: the whole ``integrate(...)`` call and
    ``Propagator.propagate_until`` (both with the drift evidence) over heyoka's
    ``propagate_until``; target <= 1.0.

    Parameters
    ----------
    study : dict
        The output of :func:`run_study` (or its JSON).

    Returns
    -------
    list of str
        One sentence per heyoka row (none when heyoka is not installed).
    """
    rows = study["rows"]
    out = []
    for peer in rows:
        if peer["method"] != "heyoka" or not peer.get("median_s") or peer["error"] is None:
            continue
        if peer["precision"] == "double" and peer["rtol"] not in (1e-9, 1e-12):
            continue
        precision = {"quad (real128)": "quad"}.get(peer["precision"], peer["precision"])
        ours = [r for r in rows if r["method"] == "taylor" and r["problem"] == peer["problem"]
                and r["precision"] == precision and r["T"] == peer["T"]
                and r.get("call_s") and r["error"] is not None
                and r["error"] <= EQUAL_ERROR_FACTOR * peer["error"]]
        what = f"{peer['problem']}, {peer['precision']}" + (
            f" tol {peer['rtol']:.0e}" if precision == "double" else "") + f", T={peer['T']:g}"
        if not ours:
            near = [r for r in rows if r["method"] == "taylor" and r["problem"] == peer["problem"]
                    and r["precision"] == precision and r["T"] == peer["T"]
                    and r.get("call_s") and r["error"] is not None]
            closest = min(near, key=lambda r: r["error"]) if near else None
            out.append(
                f"{what}: no Taylor row of ours reached heyoka's error {peer['error']:.1e}"
                + (f" (closest: {closest['error']:.1e} at rtol {closest['rtol']:.0e}, "
                   f"{closest['error'] / peer['error']:.1f}x heyoka's error, in "
                   f"{closest['call_s'] / peer['median_s']:.2f}x its time)" if closest else "")
                + " (target missed)"
            )
            continue
        best = min(ours, key=lambda r: r["call_s"])
        ratio = best["call_s"] / peer["median_s"]
        prop = best.get("propagate_s")
        pratio = prop / peer["median_s"] if prop else None
        verdict = "met" if ratio <= 1.0 else (
            "met by Propagator only" if pratio is not None and pratio <= 1.0 else "missed")
        out.append(
            f"{what}: integrate() {best['call_s'] * 1e3:.3g} ms (set-up {best['setup_s'] * 1e3:.2f}"
            f" + steps {best['median_s'] * 1e3:.3g} + evidence {best['evidence_s'] * 1e3:.2f}"
            f" ms, rtol {best['rtol']:.0e}, error {best['error']:.1e})"
            + (f", Propagator {prop * 1e3:.3g} ms" if prop else "")
            + f"; heyoka {peer['median_s'] * 1e3:.3g} ms (error {peer['error']:.1e}); ratio "
            f"{ratio:.2f}" + (f" / {pratio:.2f}" if pratio is not None else "")
            + f" (target <= 1.0: {verdict})"
        )
    return out


def _best(rows, **want):
    out = [r for r in rows if all(r.get(k) == v for k, v in want.items())
           and r["median_s"] is not None and r["error"] is not None]
    return out


def target_ratios(study: dict) -> list[str]:
    """The four targets of issue 5 §4, as measured in this run (plain sentences).

    Against heyoka measured in the same run when it is installed, else against the times
    quoted in the issue (measured on other machines; marked as such).

    Parameters
    ----------
    study : dict
        The output of :func:`run_study`; only its ``reference`` rows and ``rhs_call_s``
        are used.

    Returns
    -------
    list of str
        One sentence per target that the rows allow to assess (double and quad Taylor
        against heyoka, 50 digits against ``mpmath.odefun``, the C right-hand-side call).
    """
    rows = [r for r in study["rows"] if r["problem"] == "reference"]
    msgs = []

    def fastest(method, precision, max_error=None):
        cands = [r for r in _best(rows, method=method, precision=precision)
                 if max_error is None or r["error"] <= max_error]
        return min(cands, key=lambda r: r["median_s"]) if cands else None

    def versus(ours, peer, quoted, what):
        if peer is not None:
            return (f"{ours['median_s'] / peer['median_s']:.1f}x heyoka {what} measured in this "
                    f"run ({peer['median_s'] * 1e3:.2f} ms, error {peer['error']:.1e})")
        return (f"{ours['median_s'] / quoted:.1f}x heyoka {what} quoted in the issue "
                f"({quoted * 1e3:.0f} ms, other machine; heyoka not installed here)")

    r = fastest("taylor", "double", 1e-10)
    if r:
        msgs.append(
            f"double, error <= 1e-10 at T={r['T']:g}: Taylor {r['median_s'] * 1e3:.2f} ms "
            f"(error {r['error']:.1e}, rtol {r['rtol']:.0e}); "
            + versus(r, fastest("heyoka", "double", 1e-10), 1.0e-3, "double") + " (target <= 2x)"
        )
    else:
        msgs.append("double: no Taylor row reached error <= 1e-10 (or Taylor unavailable)")
    q = fastest("taylor", "quad", 1e-32)
    if q:
        digits = -math.log10(max(q["error"], 1e-300))
        msgs.append(
            f"quad, T={q['T']:g}: Taylor {q['median_s'] * 1e3:.1f} ms, error {q['error']:.1e} "
            f"({digits:.1f} digits); "
            + versus(q, fastest("heyoka", "quad (real128)"), 62e-3, "real128") + " (target <= 2x)"
        )
    t50 = fastest("taylor", "50 digits")
    o50 = fastest("odefun", "50 digits")
    if t50 and o50 and t50["T"] == o50["T"]:
        ratio = o50["median_s"] / t50["median_s"]
        h50 = fastest("heyoka", "50 digits")
        extra = ""
        if h50:
            extra = (f"; heyoka 50 digits {h50['median_s']:.3f} s "
                     f"(ours takes {t50['median_s'] / h50['median_s']:.2f}x its time)")
        msgs.append(
            f"50 digits, T={t50['T']:g}: Taylor {t50['median_s']:.3f} s vs mpmath.odefun "
            f"{o50['median_s']:.3f} s: {ratio:.1f}x faster (target >= 10x){extra}"
        )
    rc = study["rhs_call_s"]
    single = [k for k in rc if k.startswith("C, CompiledModel.rhs with out")]
    if single:
        fresh = [k for k in rc if k.startswith("C, CompiledModel.rhs, new output")]
        value = rc[single[0]]
        msgs.append(
            f"rhs call of the compiled C code from Python: {value * 1e9:.0f} ns per call"
            f" ({single[0].split('(')[-1].rstrip(')')}; "
            + (f"{rc[fresh[0]] * 1e9:.0f} ns with a new output array; " if fresh else "")
            + f"cffi alone {rc.get('C via cffi only (per call)', float('nan')) * 1e9:.0f} ns"
            f", batched {rc['C rhs_many, 1000 states (per state)'] * 1e9:.0f} ns per state)"
            f" (target < 300 ns: {'met' if value < 300e-9 else 'missed'})"
        )
    return msgs


