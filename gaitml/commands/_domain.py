"""The out-of-domain warning line of ``gaitml predict`` and ``gaitml pdr`` (the check itself: :mod:`gaitml.models.domain`)."""

from __future__ import annotations

import numpy as np

__all__ = ["NO_DOMAIN_WARNING", "OUT_OF_DOMAIN_WARN_FRACTION", "domain_warning"]

#: ``gaitml predict`` / ``pdr`` print one warning when more than this fraction of windows is out of domain.
OUT_OF_DOMAIN_WARN_FRACTION = 0.10
#: The warning for a model saved without a domain record.
NO_DOMAIN_WARNING = (
    "the model has no domain record (trained before gaitml recorded one), so in_domain is unknown (null); "
    "retrain it with 'gaitml train CONFIG' to get the out-of-domain check"
)


def domain_warning(model, in_domain, what: str = "windows", reasons=None) -> str | None:
    """The one warning line (without the ``gaitml: warning:`` prefix) for a prediction, or None.

    A model without a domain record gives :data:`NO_DOMAIN_WARNING`; otherwise a
    warning is given when more than :data:`OUT_OF_DOMAIN_WARN_FRACTION` of the
    ``what`` are out of domain. ``reasons`` (the ``out_of_domain_reason`` of each, optional):
    the line says how many rest between fast swings as a foot-mounted sensor does
    (:data:`gaitml.models._placement.FOOT_REASON`), or that the recording was made below the
    rates the model was trained at (:func:`gaitml.models.rate_reason`; then that alone).
    """
    from gaitml.models.domain import out_of_domain_fraction

    dom = getattr(model, "domain", None)
    if dom is None:
        return NO_DOMAIN_WARNING
    frac = out_of_domain_fraction(in_domain)
    if frac is None or frac <= OUT_OF_DOMAIN_WARN_FRACTION:
        return None
    n = len(np.asarray(in_domain, dtype=object).reshape(-1))
    k = int(round(frac * n))
    positions = ", ".join(sorted(dom.positions)) or "unknown"
    rate = rate_clause(reasons)
    if rate:
        return (
            f"{100 * frac:.1f} % of the {what} ({k} of {n}) lie outside the model's training domain{rate}; their modes are unreliable: "
            "record at the model's rates or use a model trained with data.augment.rates at this rate (docs/models.md: 'Sampling rates')"
        )
    return (
        f"{100 * frac:.1f} % of the {what} ({k} of {n}) lie outside the model's training domain (positions {positions}, "
        f"{dom.frame} frame){foot_clause(reasons)}; their modes are unreliable: use a model trained on recordings like this one "
        "(docs/models.md: 'Is my recording in the model's domain?')"
    )


def rate_clause(reasons) -> str:
    """``", every one of them because of the recording's rate: ..."`` for the warning line when the rate check flagged
    (:func:`gaitml.models.rate_reason`), else ``""``."""
    if reasons is None:
        return ""
    rates = sorted({str(r) for r in np.asarray(reasons, dtype=object).reshape(-1) if r and str(r).startswith("rate:")})
    if not rates:
        return ""
    return ", every one of them because of the recording's " + "; ".join(rates)


def foot_clause(reasons) -> str:
    """``", N of them because they rest between fast swings (...)"`` for the warning line, or ``""`` when none does."""
    from gaitml.models._placement import FOOT_REASON

    if reasons is None:
        return ""
    n_foot = int(sum(str(r) == FOOT_REASON for r in np.asarray(reasons, dtype=object).reshape(-1)))
    if not n_foot:
        return ""
    return (
        f", {n_foot} of them because they rest between fast swings (out_of_domain_reason '{FOOT_REASON}'): "
        "a foot-mounted sensor shows this at every stride, no phone carried by a walker does, a gesturing hand can"
    )
