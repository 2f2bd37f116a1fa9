"""The deformation course's feedback pictures: the student's deformation or weights beside the reference's.

The engine (``grader.pipeline.feedback``) calls :func:`pictures` on one hidden
case of each function in ``PICTURED``, a failed case first; ``value`` is the
student's collected output (hostile: only numbers are drawn, and the
interactive views validate it), ``expected`` the reference's.
"""

from __future__ import annotations

import numpy as np

from grader.pipeline.feedback import pair_figure, picture
from grader.pipeline.feedback_view import deformation_view, student_array, weights_view

PICTURED = ("k_harmonic_solve", "arap_solve", "laplacian_editing", "bbw", "unconstrained_biharmonic_weights")


def pictures(function: str, case, value, expected) -> list[dict]:
    """Pictures of ``function`` on ``case``; the first carries the interactive view of the same case.

    Parameters
    ----------
    function : str
        One of ``PICTURED``.
    case : grader.checks.base.Case
        The hidden case; the mesh ``(V, F)`` and the handles are its first step's arguments.
    value : Any
        The student's output.
    expected : Any
        The reference's output.

    Returns
    -------
    list of dict
        ``{"caption", "alt", "png"}`` each, ``"view"`` on the first; empty when the output cannot be drawn.
    """
    if function == "k_harmonic_solve":
        return _k_harmonic_solve(case, value, expected)
    args = case.steps[0].args
    V, F = np.asarray(args[0], float), np.asarray(args[1], np.int64)
    if function == "arap_solve":
        return _arap_solve(case, V, F, value, expected)
    if function == "laplacian_editing":
        pics = [picture(
            f"{function}, {case.label}: your edited mesh (left) beside the reference's (right).",
            f"Two meshes side by side: the result of your {function} and the reference's, on hidden case {case.label}.",
            pair_figure(np.asarray(value, float), np.asarray(expected), F, titles=("your laplacian_editing", "reference")),
        )]
        pics[0]["view"] = view(function, case, value, expected)
        return pics
    W, W_ref = np.asarray(value, float), np.asarray(expected, float)
    if V.shape[1] != 2 or W.shape != W_ref.shape:
        return []
    pics = [picture(
        f"{function}, {case.label}: weight of handle 1 on every vertex, yours (left) beside the reference's (right); "
        "blue is 0, red is 1, darker colours lie outside [0, 1].",
        f"Two colour maps of the weight of handle 1 over the mesh: yours and the reference's, on hidden case {case.label}.",
        pair_figure(V, V, F, W[:, 0], W_ref[:, 0], titles=(f"your {function}", "reference"), label="weight of handle 1"),
    )]
    pics[0]["view"] = view(function, case, value, expected)
    return pics


def view(function: str, case, value, expected) -> dict | None:
    """The interactive view of one hidden case (``grader.pipeline.feedback_view``), from the same data as its picture.

    ``value`` is the student's output, validated by the view; None for a function without a view.
    """
    if function == "k_harmonic_solve":
        V, F = case.context["mesh"]
        got = student_array(value, V.shape)
        handles = np.asarray(case.steps[0].args[1], np.int64)
        return deformation_view(V, F, handles, None if got is None else V + got, V + np.asarray(expected, float))
    args = case.steps[0].args
    V, F = np.asarray(args[0], float), np.asarray(args[1], np.int64)
    if function == "arap_solve":
        got = value[0] if isinstance(value, tuple) and len(value) == 2 else None
        return deformation_view(V, F, np.asarray(args[2], np.int64), got, np.asarray(expected[0], float))
    if function == "laplacian_editing":
        return deformation_view(V, F, np.asarray(args[2], np.int64), value, np.asarray(expected, float))
    if function in ("bbw", "unconstrained_biharmonic_weights"):
        b, bc = np.asarray(args[2], np.int64), np.asarray(args[3], float)
        groups = [b[np.argmax(bc, axis=1) == j] for j in range(bc.shape[1])]
        return weights_view(V, F, groups, value, np.asarray(expected, float))
    return None


def _k_harmonic_solve(case, value, expected) -> list[dict]:
    """The student's deformed mesh ``V + D`` beside the reference's (the mesh is kept in the case's context)."""
    V, F = case.context["mesh"]
    D, D_ref = student_array(value, V.shape), np.asarray(expected, float)
    if D is None:
        return []
    pics = [picture(
        f"k_harmonic_solve, {case.label}: your deformed mesh V + D (left) beside the reference's (right).",
        f"Two meshes side by side: the rest mesh moved by your displacements and by the reference's, on hidden case {case.label}.",
        pair_figure(V + D, V + D_ref, F, titles=("your V + D", "reference")),
    )]
    pics[0]["view"] = view("k_harmonic_solve", case, value, expected)
    return pics


def _arap_solve(case, V: np.ndarray, F: np.ndarray, value, expected) -> list[dict]:
    """The deformed mesh beside the reference's, and both energy curves (local-global never increases it)."""
    import matplotlib.pyplot as plt

    U, energies = np.asarray(value[0], float), np.asarray(value[1], float).ravel()
    pics = [picture(
        f"arap_solve, {case.label}: your deformed mesh (left) beside the reference's (right).",
        f"Two meshes side by side: the deformation computed by your arap_solve and the reference's, on hidden case {case.label}.",
        pair_figure(U, np.asarray(expected[0]), F, titles=("your arap_solve", "reference")),
    )]
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.semilogy(np.arange(1, len(energies) + 1), np.maximum(energies, 1e-300), "o-", label="yours")
    ax.semilogy(np.arange(1, len(expected[1]) + 1), np.maximum(np.asarray(expected[1], float), 1e-300), "s--", label="reference")
    ax.set_xlabel("iteration")
    ax.set_ylabel("ARAP energy (log scale)")
    ax.set_title(f"ARAP energy per iteration, {case.label}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    pics.append(picture(
        f"arap_solve, {case.label}: energy after each iteration, yours (circles) and the reference's (squares). "
        "Local-global iterations never increase the energy.",
        f"Line plot of the ARAP energy per iteration: {len(energies)} values of yours, {len(expected[1])} of the reference.",
        fig,
    ))
    pics[0]["view"] = view("arap_solve", case, value, expected)
    return pics
