"""Proofs by computation on enclosures: the Krawczyk test for a zero of a map and the
Schur-Cohn test for the multipliers of a matrix, both decided in Arb ball arithmetic.

* :func:`krawczyk_test`: for ``F: R^n -> R^n`` with an enclosure ``F(x^)`` at a point and
  ``DF(X)`` over a box ``X`` containing it, ``K = x^ - C F(x^) + (Id - C DF(X)) (X - x^)``
  (``C`` any matrix, here ``mid(DF)^-1``); ``K ⊆ int X`` proves that ``F`` has exactly one
  zero in ``X`` (Krawczyk 1969; Moore 1977), and ``K ∩ X = ∅`` that it has none.
* :func:`schur_cohn`: the characteristic polynomial of every matrix in an interval matrix,
  reduced by Schur-Cohn steps ``p -> (a_n p - a_0 p*)/z``: all ``|a_0| < |a_n|`` proves every
  eigenvalue strictly inside the unit circle (Jury's criterion); a step with ``|a_0| > |a_n|``
  proves one on or outside it (Rouché's theorem counts the zeros: ``N_in(p) = 1 + N_in(Tp)``
  when ``|a_n| > |a_0|``, and ``N_out(p) = 1 + N_in(Tp)`` when ``|a_0| > |a_n|`` and ``p`` has
  no zero on the circle); an undecided comparison leaves the question open.
"""

from __future__ import annotations

from dataclasses import dataclass

from flint import arb_mat

__all__ = ["KrawczykResult", "krawczyk_test", "schur_cohn"]


@dataclass
class KrawczykResult:
    """The outcome of :func:`krawczyk_test`.

    Attributes
    ----------
    verdict : {"unique zero", "no zero", "undecided"}
    image : list of arb
        The Krawczyk box ``K``.
    margin : float
        The smallest gap between ``K`` and the boundary of ``X``, relative to ``X``'s radius
        (positive when ``K ⊆ int X``; negative otherwise).
    """

    verdict: str
    image: list
    margin: float


def krawczyk_test(centre: list, box: list, F_centre: list, DF_box: arb_mat) -> KrawczykResult:
    """The Krawczyk test on a box.

    Parameters
    ----------
    centre : list of arb
        ``x^`` (a point or a small ball), inside ``box``.
    box : list of arb
        ``X``.
    F_centre : list of arb
        An enclosure of ``F`` over ``centre``.
    DF_box : arb_mat
        An enclosure of the derivative of ``F`` over ``box``.

    Returns
    -------
    KrawczykResult

    Examples
    --------
    >>> from flint import arb, arb_mat
    >>> X = [arb("1.4142", "0.001")]           # F(x) = x^2 - 2 on [1.4132, 1.4152]
    >>> r = krawczyk_test([arb("1.4142")], X, [arb("1.4142") ** 2 - 2], arb_mat([[2 * X[0]]]))
    >>> r.verdict
    'unique zero'
    """
    n = len(box)
    mid = arb_mat([[DF_box[i, j].mid() for j in range(n)] for i in range(n)])
    try:
        C = mid.inv()
    except ZeroDivisionError:  # the midpoint derivative is singular: nothing to decide with
        return KrawczykResult("undecided", list(box), float("-inf"))
    C = arb_mat([[C[i, j].mid() for j in range(n)] for i in range(n)])
    eye = arb_mat([[1 if i == j else 0 for j in range(n)] for i in range(n)])
    dx = arb_mat([[box[i] - centre[i]] for i in range(n)])
    K = (
        arb_mat([[c] for c in centre])
        - C * arb_mat([[f] for f in F_centre])
        + (eye - C * DF_box) * dx
    )
    image = [K[i, 0] for i in range(n)]
    inside = all(box[i].contains_interior(image[i]) for i in range(n))
    margin = min(
        (float(box[i].rad()) - float(abs(image[i] - box[i].mid()).upper())) / float(box[i].rad())
        for i in range(n)
    )
    if inside:
        return KrawczykResult("unique zero", image, margin)
    if any(not box[i].overlaps(image[i]) for i in range(n)):
        return KrawczykResult("no zero", image, margin)
    return KrawczykResult("undecided", image, margin)


def schur_cohn(matrix: arb_mat) -> tuple[str, list]:
    """Whether every eigenvalue of every matrix in an interval matrix lies strictly inside
    the unit circle.

    Parameters
    ----------
    matrix : arb_mat
        A square interval matrix.

    Returns
    -------
    verdict : {"inside", "not inside", "undecided"}
        ``"inside"``: proved for every matrix in the box; ``"not inside"``: proved that every
        matrix in the box has an eigenvalue of modulus ``>= 1``; ``"undecided"`` otherwise.
    steps : list of (arb, arb)
        ``(|a_0|, |a_n|)`` of each Schur-Cohn step.

    Examples
    --------
    >>> from flint import arb_mat
    >>> schur_cohn(arb_mat([[0.5, 0.3], [-0.3, 0.5]]))[0]
    'inside'
    >>> schur_cohn(arb_mat([[0.5, 0.9], [-0.9, 0.5]]))[0]
    'not inside'
    """
    poly = matrix.charpoly()
    a = [poly[k] for k in range(poly.degree() + 1)]
    steps = []
    while len(a) > 1:
        lo, hi = abs(a[0]), abs(a[-1])
        steps.append((lo, hi))
        if lo < hi:
            n = len(a) - 1
            a = [a[-1] * a[k + 1] - a[0] * a[n - k - 1] for k in range(n)]
            continue
        if lo > hi:
            return "not inside", steps
        return "undecided", steps
    return "inside", steps
