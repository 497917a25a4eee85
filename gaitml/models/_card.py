"""The model card: a markdown summary of a model folder, generated from its ``model.json``.

Written as ``MODEL.md`` when a model is saved and printed by ``gaitml model card
MODEL_DIR``. It states what a user needs to judge whether the model fits their
data: training data (source, subjects, positions, modes, duration), the
cross-validation scores (overall and per class when recorded), window settings,
feature set, the domain the model is valid for, known failure cases and the
library versions. Everything comes from ``model.json``; nothing is measured here.
"""

from __future__ import annotations

import numpy as np

from gaitml.errors import ModelError

__all__ = ["model_card"]

_KIND_TEXT = {
    "linear-ovo-svm": "linear SVM trained one pair of classes at a time, majority vote (paper 003 sec. 3.1, 3.3) on standardised features",
    "mlp": "small multilayer perceptron (torch) on standardised features (a baseline, not in paper 003)",
    "cnn1d": "small 1-D convolutional network (torch) on raw window samples (a baseline, not in paper 003)",
}

#: Failure cases that hold for every gaitml motion-mode model (from the design of the features and windows).
_GENERAL_FAILURES = (
    "Modes outside its label set are forced onto one of its labels (there is no 'unknown' class).",
    "Windows that straddle a mode change take either mode; the adjacent-window correction (paper 003 sec. 3.4) "
    "removes single-window blips but delays the output by one window.",
    "The features are computed in the phone frame: a carrying position or orientation not in the training data "
    "(pocket, bag, swinging hand when trained on a hand-held phone) changes them and lowers accuracy.",
    "Recordings at another rate are resampled to the model's rate first; rates far below it lose the step harmonics.",
)


def _fmt(v, digits: int = 3) -> str:
    if isinstance(v, float):
        return f"{v:.{digits}f}"
    return str(v)


def _training_lines(info: dict) -> list[str]:
    cfg = info.get("training_config") or {}
    data = cfg.get("data") or {}
    td = info.get("training_data") or {}
    lines = []
    src = data.get("source", "unknown")
    lines.append(f"- Source: {src}" + (f" (`{data['path']}`)" if data.get("path") else ""))
    sim = data.get("simulated") or {}
    if src == "simulated" and sim:
        lines.append(
            f"- Simulated by gaitml.simulate: {sim.get('subjects')} subjects x {sim.get('sessions', 1)} session(s), "
            f"{_fmt(float(sim.get('duration_s', 0)), 0)} s each, phone pose {sim.get('pose', 'flat')}, seed {cfg.get('seed')}"
        )
        modes = sim.get("modes") or info.get("labels")
        lines.append(f"- Modes: {', '.join(map(str, modes))}")
        n_rec = td.get("n_recordings")
        if n_rec and sim.get("duration_s"):
            lines.append(f"- Duration: {n_rec} recordings, {float(n_rec) * float(sim['duration_s']) / 60:.0f} min in total")
    else:
        lines.append(f"- Modes (labels): {', '.join(map(str, info.get('labels', [])))}")
    groups = td.get("groups") or []
    if groups:
        key = data.get("group", "group")
        shown = ", ".join(map(str, groups[:8])) + (", ..." if len(groups) > 8 else "")
        lines.append(f"- Subjects / groups ({key}): {len(groups)}: {shown}")
    where = data.get("where") or {}
    if where:
        lines.append("- Selection: " + "; ".join(f"{k} = {v}" for k, v in where.items()))
    positions = td.get("positions") or where.get("position")
    if positions:
        lines.append(f"- Phone positions: {positions if isinstance(positions, str) else ', '.join(map(str, positions))}")
    elif src == "simulated":
        # models that do not record the tilted range were trained with the simulator's 30-50 deg
        lo, hi = td.get("hand_tilted_pitch_deg") or (30.0, 50.0)
        lines.append(
            f"- Phone positions: held in the hand, pose {sim.get('pose', 'flat')} (flat: pitch about 3-12 deg, tilted: {lo:.0f}-{hi:.0f} deg; "
            "mixed: drawn per subject); no pocket, bag or swinging-hand recordings"
        )
    if td.get("n_windows") is not None:
        lines.append(f"- Training windows: {td['n_windows']}")
    for note in td.get("notes") or []:
        lines.append(f"- Note: {note}")
    card = cfg.get("card") or {}
    if card.get("licence"):
        lines.append(f"- Licence of the training data: {card['licence']}")
    lines += _source_lines(td.get("sources") or [], [str(x) for x in info.get("labels", [])])
    if card.get("notes"):
        lines += ["", *(f"- {n}" for n in card["notes"])]
    return lines


def _source_lines(sources: list[dict], labels: list[str]) -> list[str]:
    """Training windows per source (real / simulated), position and label: which modes were learnt from what."""
    kinds = {s.get("kind") for s in sources}
    if len(kinds) < 2:  # one kind of data: the lines above say it
        return []
    out = [
        "",
        "Training windows by source and carrying position (real recordings: the position is the recording's motion):",
        "",
        "| source | position | " + " | ".join(labels) + " |",
        "|---|---|" + "---|" * len(labels),
    ]
    for s in sources:
        w = s.get("windows") or {}
        out.append(f"| {s.get('kind')} | {s.get('position')} | " + " | ".join(str(w.get(lab, 0)) for lab in labels) + " |")
    for kind in sorted(kinds):
        learnt = sorted({lab for s in sources if s.get("kind") == kind for lab, n in (s.get("windows") or {}).items() if n})
        out.append(f"- {kind.capitalize()} windows teach: {', '.join(learnt)}")
    return out


def _cv_lines(info: dict) -> list[str]:
    cv = info.get("cv_scores")
    if not cv:
        return ["Not recorded (the model was trained with `train.cross_validate = false`)."]
    lines = [
        f"Scheme: {cv.get('scheme', '?')}, {cv.get('n_folds', '?')} folds, {cv.get('n_test_predictions', '?')} test windows"
        + (
            " (the recordings as they were: the augmented copies train every fold and are not scored)."
            if cv.get("copies_not_scored")
            else "."
        ),
        "",
        "| | before correction | after correction |",
        "|---|---|---|",
        f"| accuracy (pooled) | {_fmt(cv.get('accuracy_before'))} | {_fmt(cv.get('accuracy_after'))} |",
        f"| macro F1 (pooled) | {_fmt(cv.get('macro_f1_before'))} | {_fmt(cv.get('macro_f1_after'))} |",
        f"| fold accuracy mean +- std | {_fmt(cv.get('fold_accuracy_mean_before'))} +- {_fmt(cv.get('fold_accuracy_std_before'))} "
        f"| {_fmt(cv.get('fold_accuracy_mean_after'))} +- {_fmt(cv.get('fold_accuracy_std_after'))} |",
    ]
    pcb, pca = cv.get("per_class_before"), cv.get("per_class_after")
    if pcb:
        lines += [
            "",
            "Per class (pooled over folds; after = with the adjacent-window correction):",
            "",
            "| class | precision | recall | F1 | F1 after | support |",
            "|---|---|---|---|---|---|",
        ]
        for lab, m in pcb.items():
            after = (pca or {}).get(lab, {}).get("f1")
            lines.append(
                f"| {lab} | {_fmt(m['precision'])} | {_fmt(m['recall'])} | {_fmt(m['f1'])} | {_fmt(after) if after is not None else '-'} | {m['support']} |"
            )
        if cv.get("per_class_source"):
            lines += ["", f"Per-class source: {cv['per_class_source']}"]
    else:
        lines += ["", "Per-class scores were not recorded for this model."]
    return lines


def _domain_lines(info: dict) -> list[str]:
    """The "Domain" section: the recorded training domain and how windows are checked (gaitml.models.domain)."""
    dom = info.get("domain")
    if not isinstance(dom, dict):
        return [
            "No domain record: this model was saved before gaitml recorded one, so `gaitml predict` and `gaitml pdr` "
            "cannot say whether a window is like its training data (`in_domain` is null). Retrain it with `gaitml train CONFIG`."
        ]
    sm = dom.get("summary") or {}
    pos = dom.get("positions") or {}
    lines = [
        "- Positions: " + (", ".join(f"{k} ({v} windows)" for k, v in pos.items()) or "unknown"),
        f"- Feature frame: `{info.get('feature_frame', 'phone')}`"
        + (
            " (the phone's own axes: the features change when the phone is held another way)"
            if info.get("feature_frame", "phone") == "phone"
            else " (per-window gravity-aligned: the features do not depend on the phone's orientation)"
        ),
    ]
    if info.get("acc_range_ms2") is not None:
        lines.append(
            f"- Accelerometer range: every recording is read through +-{float(info['acc_range_ms2']):g} m/s^2 per axis "
            "(the narrowest range of the training phones) before the features and this check; a phone with a wider range is "
            "not out of domain merely for reading beyond it. The foot-placement rule reads the recording unclipped."
        )
    try:
        g = sm.get("gravity_mean") or []
        q = sm.get("gravity_angle_to_mean_deg") or {}
        lines.append(
            f"- Gravity direction in the phone frame: mean unit vector ({', '.join(f'{float(v):.3f}' for v in g)}); angle to it "
            + ", ".join(f"{k[1:]} % {float(v):.1f} deg" for k, v in q.items())
            + f"; {sm.get('gravity_directions_kept', '?')} training directions kept"
        )
        lines.append(
            f"- Feature distance: smallest Mahalanobis distance to the classes' Gaussians (Ledoit-Wolf) on `{dom.get('feature_set')}` "
            f"in the {dom.get('frame')} frame; threshold {float(dom['distance_threshold']):.2f} = the {float(dom['quantile']):g} "
            f"quantile of held-out distances ({sm.get('heldout', '?')}); in-sample it would be {float(dom['distance_threshold_in_sample']):.2f}"
        )
        if dom.get("gravity_check"):
            lines.append(
                f"- Gravity check: a window whose gravity direction is more than {np.degrees(float(dom['gravity_threshold_rad'])):.1f} deg "
                f"from every kept training direction is out of domain (held-out {float(dom['quantile']):g} quantile; in-sample "
                f"{np.degrees(float(dom['gravity_threshold_in_sample_rad'])):.1f} deg)"
            )
        else:
            lines.append("- Gravity check: off (gravity-frame features do not depend on the phone's orientation)")
        dyn = dom.get("dynamics")
        if isinstance(dyn, dict):
            every = int(dyn.get("every", 1))  # records before the grid: every window
            grid = f" (of the distances of one window in {every}: windows 0, {every}, {2 * every}, ...)" if every > 1 else ""
            lines.append(
                f"- Orientation dynamics (how the phone moves and turns; independent of how it is held): smallest Mahalanobis "
                f"distance to {len(dyn['labels'])} mode|position Gaussians, median over the last {int(dyn['span'])} windows of the "
                f"recording{grid}; threshold {float(dyn['threshold']):.2f} (held-out {float(dom['quantile']):g} quantile; in-sample "
                f"{float(dyn['threshold_in_sample']):.2f}): a stretch carried unlike every training position is out of domain"
            )
        if dom.get("acc_range_ms2") is not None:
            lines.append(
                f"- Accelerometer range of the check: the three parts above read every recording clipped to +-{float(dom['acc_range_ms2']):g} "
                "m/s^2 per axis, as they were fitted (the classifier reads it as it comes): a phone reading beyond the training "
                "phones' narrowest range is compared on what every training phone could report"
            )
    except (KeyError, TypeError, ValueError):
        lines.append("- (the domain record is incomplete)")
    if sm.get("recorded"):
        lines.append(f"- Domain recorded {sm['recorded']}")
    lines.append(
        "- `gaitml predict` marks each window `in_domain`, reports `out_of_domain_fraction` and warns above 10 %; "
        "`gaitml pdr --model` moves out-of-domain steps forward along the facing heading (`out_of_domain_steps`)."
    )
    lines.append(_placement_line(pos))
    lines.append(_rate_line(info, dom))
    return lines


def _rate_line(info: dict, dom: dict) -> str:
    """The sampling rates the model answers at (the rate check, gaitml.models.rate_reason)."""
    from gaitml.models.domain import RATE_TOLERANCE

    fs = float(info.get("sampling_rate_hz", 0.0))
    low = dom.get("min_rate_hz")
    if low is None:
        return (
            "- Sampling rates: not recorded (a model saved before gaitml kept its training rates): a recording made at any "
            f"rate is resampled to {fs:g} Hz and not checked for its rate."
        )
    low = float(low)
    rates = ((info.get("training_config") or {}).get("data", {}).get("augment") or {}).get("rates") or []
    how = (
        f" (its recordings also trained as copies taken down to {', '.join(f'{float(r):g}' for r in rates)} Hz and back up: "
        "data.augment.rates)"
        if rates
        else ""
    )
    return (
        f"- Sampling rates: trained on recordings carrying {low:g} Hz and above{how}; every recording is resampled to {fs:g} Hz. "
        f"A recording made below {RATE_TOLERANCE * low:g} Hz ({RATE_TOLERANCE:g} x {low:g}) has every window out of domain with "
        f"`out_of_domain_reason` 'rate: recorded at ... Hz, below the {low:.3g} Hz the model was trained at'."
    )


def _placement_line(positions) -> str:
    """The foot-placement rule (gaitml.models._placement) as it applies to a model trained on ``positions``."""
    from gaitml.models._placement import FOOT_REASON

    if any(str(p).lower().startswith("foot") for p in positions):
        return "- Foot-placement rule: not applied (a foot position is in the training data)."
    return (
        "- Foot-placement rule: a window holding a rest between fast swings, as a foot-mounted sensor shows at every "
        "stride and no phone carried by a walker does (a gesturing hand can; a fixed physics rule, not fitted to this "
        f"model), is out of domain with `out_of_domain_reason` '{FOOT_REASON}'."
    )


def _convergence_lines(info: dict) -> list[str]:
    """How the solver stopped (linear OVO SVM; recorded since training to convergence, see gaitml.models._svm)."""
    est = info.get("estimator") or {}
    state, params = est.get("state") or {}, est.get("params") or {}
    if info.get("model_kind") != "linear-ovo-svm" or "n_iter_max_" not in state:
        return []
    line = (
        f"- Solver: {'converged' if state.get('converged_') else 'NOT converged'} for every class pair "
        f"(at most {int(state['n_iter_max_'])} iterations of max_iter = {params.get('max_iter')})"
    )
    if state.get("gradient_norm_max_") is not None:
        line += (
            f"; largest final gradient norm {float(state['gradient_norm_max_']):.1e}, so every standardised weight and bias "
            "is within that of the exact optimum (the objective is 1-strongly convex): a retrain on another machine gives "
            "the same model up to about twice that"
        )
    return [line]


def model_card(info: dict) -> str:
    """Markdown model card of a model described by ``info`` (its ``model.json``).

    Raises
    ------
    ModelError
        ``info`` lacks the entries every model.json has (kind, window, labels).
    """
    try:
        kind = info["model_kind"]
        win = info["window"]
        labels = list(info["labels"])
        fs = float(info["sampling_rate_hz"])
    except (KeyError, TypeError, ValueError) as exc:
        raise ModelError(f"model.json lacks {exc}; it is not a complete gaitml model description.") from exc
    name = info.get("name") or (info.get("training_config") or {}).get("name") or "model"
    fset = info.get("feature_set")
    desc = (info.get("training_config") or {}).get("description")
    length = int(round(float(win["length_s"]) * fs))
    hop = max(1, int(round(length * (1 - float(win["overlap"])))))
    out = [f"# Model card: {name}", ""]
    if desc:
        out += [desc, ""]
    out += [
        "## Model",
        "",
        f"- Kind: `{kind}`: {_KIND_TEXT.get(kind, kind)}",
        "- Parameters: "
        + ", ".join(f"{k} = {v}" for k, v in (info.get("estimator", {}).get("params") or info.get("model_params") or {}).items()),
        f"- Classes: {', '.join(map(str, labels))}",
        *_convergence_lines(info),
        f"- Created: {info.get('created_utc', '?')}" + (" (converted from a pickle model, format 1)" if info.get("converted_from") else ""),
        "- Files: `model.json` (settings, hashes), `arrays.npz` (numbers)"
        + (", `weights.pt` (torch state_dict)" if "weights.pt" in (info.get("files") or {}) else ""),
        "",
        "## Input",
        "",
        f"- Sampling rate: {fs:g} Hz (other rates are resampled to it)",
        f"- Windows: {float(win['length_s']):g} s ({length} samples), overlap {float(win['overlap']):g} (hop {hop} samples); "
        f"training windows needed a majority label over {float(win.get('min_label_fraction', 0.5)):g} of the samples",
    ]
    if win.get("by", "time") != "time":  # step-synchronous windows (gaitml.features.step_windows)
        out[-1] = (
            f"- Windows: one per detected {str(win['by']).rstrip('s')} ({win['by']} of detector `{win.get('detector')}`), "
            f"features on the {str(win['by']).rstrip('s')}'s own samples; training windows needed a majority label over "
            f"{float(win.get('min_label_fraction', 0.5)):g} of the samples"
        )
    if info.get("input_kind") == "raw":
        out.append(f"- Raw channels: {', '.join(info.get('raw_channels', []))} (standardised per channel)")
    else:
        n = len(info.get("feature_names", []))
        gyro = "gyro" in str(fset)
        out.append(
            f"- Feature set: `{fset}`, {n} features (paper 003 sec. 3.2, F numbers in `features/catalogue.md`"
            + ("; G1..G52 are the same statistics of the gyroscope" if gyro else "")
            + ")"
        )
        out.append(f"- Sensors needed: accelerometer (m/s^2){' and gyroscope (rad/s)' if gyro else ''}")
    pp = info.get("postprocess") or {}
    out.append(f"- Adjacent-window correction (paper 003 sec. 3.4): {'on' if pp.get('adjacent_correction', True) else 'off'}")
    out += ["", "## Training data", "", *_training_lines(info), "", "## Cross-validation", "", *_cv_lines(info)]
    src = ((info.get("training_config") or {}).get("data") or {}).get("source")
    out += ["", "## Domain it is valid for", ""]
    sim_positions = (((info.get("training_config") or {}).get("data") or {}).get("simulated") or {}).get("positions") or []
    if src == "simulated":
        carried = f"carrying the phone {', '.join(map(str, sim_positions))}" if sim_positions else "with the phone held in the hand"
        out.append(
            f"Simulated walkers ({', '.join(map(str, labels))}) {carried}. The scores above are on simulated "
            "subjects it was not trained on; on real recordings expect lower accuracy until it is checked on them."
        )
    else:
        out.append(f"Recordings like the training data above: the same modes ({', '.join(map(str, labels))}), phone positions and sensors.")
    out += ["", "## Domain", "", *_domain_lines(info)]
    failures = list(_GENERAL_FAILURES)
    if info.get("feature_frame", "phone") == "gravity":
        failures[2] = (
            "The features are computed in a per-window gravity-aligned frame: the phone's orientation does not change them, "
            "but a carrying position moves the phone with another body segment (thigh, arm, bag), which does."
        )
    elif sim_positions:
        failures[2] = (
            "The features are computed in the phone frame: a carrying position or phone orientation unlike the simulated "
            f"ones ({', '.join(map(str, sim_positions))}) changes them and lowers accuracy; the domain check flags it."
        )
    out += ["", "## Known failure cases", ""] + [f"- {t}" for t in failures]
    if "gyro" in str(fset):
        out.append("- Accelerometer-only recordings are refused (the feature set needs a gyroscope); use a model on `all52`.")
    out += ["", "## Versions", ""]
    out += [f"- {k}: {v}" for k, v in (info.get("versions") or {}).items()]
    conv = info.get("converted_from")
    if conv:
        out += [f"- converted from format {conv.get('format_version')} ({conv.get('file')}, sha256 {str(conv.get('sha256'))[:12]}...)"]
    return "\n".join(out) + "\n"
