"""The step detectors' rate floors (gaitml.steps._rate): a recording made below the lowest rate a detector's count
holds at is counted as always and flagged (API attrs, CLI table / JSON / one stderr line), at or above it not."""

from __future__ import annotations

import importlib
import json

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.io import write_gaitml_csv
from gaitml.models import resample_recording
from gaitml.simulate import Subject, simulate_recording
from gaitml.steps import DETECTORS, RATE_TOLERANCE, add_rate_reasons, get_detector, rate_flags, rate_floors, rate_record, rate_warning
from tests.conftest import shared

FLOORED = "single-peak"  # floor 50 Hz: a 20 Hz phone is below it, adaptive (15 Hz) is not
WARN = "down to which"  # the words of the stderr line (and of every reason)


@pytest.fixture(scope="module")
def walk():
    """A simulated walk (phone in hand) at 50 Hz, 40 s, with a gyroscope."""
    return simulate_recording(Subject(), modes=("walk",), duration_s=40.0, seed=5)


@pytest.fixture(scope="module")
def files(walk, tmp_path_factory):
    """The walk recorded at 50, 20 and 10 Hz, as gaitml CSV files."""
    d = tmp_path_factory.mktemp("rates")
    out = {}
    for fs in (50.0, 20.0, 10.0):
        out[fs] = d / f"walk{fs:g}.csv"
        write_gaitml_csv(resample_recording(walk, fs), out[fs])
    return out


def _warn_lines(err: str) -> list[str]:
    return [ln for ln in err.splitlines() if WARN in ln]


# ---- the floors


def test_every_detector_declares_a_floor_as_a_module_constant():
    floors = rate_floors()
    assert set(floors) == set(DETECTORS.names())
    for name, cls in ((n, DETECTORS[n]) for n in DETECTORS.names()):
        mod = importlib.import_module(cls.__module__)
        consts = {v for k, v in vars(mod).items() if k.endswith("RATE_FLOOR_HZ")}
        assert floors[name] in consts and 5.0 <= floors[name] <= 100.0, name
    # the same tolerance as a model's rate check
    from gaitml.models.domain import RATE_TOLERANCE as MODEL_TOLERANCE

    assert RATE_TOLERANCE == MODEL_TOLERANCE


@pytest.mark.parametrize("name", DETECTORS.names())
def test_below_the_floor_is_flagged_at_it_not_and_the_count_is_the_detectors_own(walk, name):
    floor = DETECTORS[name].rate_floor_hz
    at, below = resample_recording(walk, floor) if floor != 50.0 else walk, resample_recording(walk, 0.85 * floor)
    det = get_detector(name)
    ok = det.detect(at).steps_.attrs["rate_check"]
    assert ok["below"] is False and ok["reason"] == "" and ok["floor_hz"] == floor and ok["detector"] == name
    steps = get_detector(name).detect(below).steps_
    check = steps.attrs["rate_check"]
    assert check["below"] is True and check["recorded_hz"] == pytest.approx(0.85 * floor)
    assert check["reason"].startswith(f"rate: recorded at {0.85 * floor:.3g} Hz, below the {floor:.3g} Hz")
    assert rate_flags(steps)[0].all()
    # the flag adds nothing to the steps: the same table as the detector's own detect without the check
    raw = get_detector(name)
    type(raw).detect.__wrapped__(raw, below)
    pd.testing.assert_frame_equal(raw.steps_, steps)


def test_a_rate_just_under_the_floor_is_within_the_tolerance(walk):
    floor = DETECTORS[FLOORED].rate_floor_hz
    near = get_detector(FLOORED).detect(resample_recording(walk, RATE_TOLERANCE * floor)).steps_
    assert near.attrs["rate_check"]["below"] is False


def test_a_recording_resampled_up_is_judged_at_the_rate_it_was_made_at(walk):
    up = resample_recording(resample_recording(walk, 20.0), 50.0)
    assert up.sampling_rate_hz == 50.0
    check = get_detector(FLOORED).detect(up).steps_.attrs["rate_check"]
    assert check["below"] is True and check["recorded_hz"] == 20.0
    assert get_detector("adaptive").detect(up).steps_.attrs["rate_check"]["below"] is False


def test_a_recording_resampled_up_twice_keeps_the_rate_it_was_made_at(walk):
    """Each resampling used to record only the rate just before it: a 20 Hz walk brought to 50 then 100 Hz read
    as made at 50 Hz (single-peak's floor: not flagged), a 10 Hz walk brought to 20 then 50 Hz as 20 Hz (adaptive's
    15 Hz floor: not flagged, where one tyrex person's count loses 0.14)."""
    twice = resample_recording(resample_recording(resample_recording(walk, 20.0), 50.0), 100.0)
    assert twice.sampling_rate_hz == 100.0 and twice.meta["resampled_from_hz"] == 20.0
    check = get_detector(FLOORED).detect(twice).steps_.attrs["rate_check"]
    assert check["below"] is True and check["recorded_hz"] == 20.0
    slow = resample_recording(resample_recording(resample_recording(walk, 10.0), 20.0), 50.0)
    check = get_detector("adaptive").detect(slow).steps_.attrs["rate_check"]
    assert check["below"] is True and check["recorded_hz"] == 10.0
    # taken down and back up: the rate it passed through; a plain down-sampling: its own rate
    assert resample_recording(resample_recording(walk, 20.0), 50.0).meta["resampled_from_hz"] == 20.0
    down = resample_recording(walk, 20.0)
    assert down.meta["resampled_from_hz"] == 50.0
    assert get_detector("adaptive").detect(down).steps_.attrs["rate_check"]["recorded_hz"] == 20.0


def test_a_slow_stretch_flags_only_its_steps(walk):
    rec = walk.replace(meta={**walk.meta, "rate_changes": [[10.0, 20.0, 20.0]]}, check_units=False)
    steps = get_detector(FLOORED).detect(rec).steps_
    check = steps.attrs["rate_check"]
    assert check["below"] is False and check["stretches_below"] == [[10.0, 20.0, 20.0]]
    flagged, why = rate_flags(steps)
    t = steps["t_peak_s"].to_numpy()
    inside = (t >= 10.0) & (t < 20.0)
    assert inside.any() and (~inside).any()
    assert (flagged == inside).all() and all(w.startswith("rate: recorded at 20 Hz") for w in why[inside])
    rec_ = rate_record(steps)
    assert rec_["n_steps_below"] == int(inside.sum()) and rec_["n_steps"] == len(steps)
    line = rate_warning(rec_)
    assert f"{int(inside.sum())} of its {len(steps)} steps" in line and "\n" not in line
    # a stretch above the floor flags nothing
    fine = walk.replace(meta={**walk.meta, "rate_changes": [[10.0, 20.0, 48.0]]}, check_units=False)
    assert rate_warning(rate_record(get_detector(FLOORED).detect(fine).steps_)) is None


def test_add_rate_reasons_puts_the_column_on_a_table_only_when_a_step_is_flagged(walk):
    # the one helper behind the rate_reason column of gaitml steps, segment, the labeller and the PDR tables
    rec = walk.replace(meta={**walk.meta, "rate_changes": [[10.0, 20.0, 20.0]]}, check_units=False)
    steps = get_detector(FLOORED).detect(rec).steps_
    flagged, why = rate_flags(steps)
    table = steps.copy()
    assert (add_rate_reasons(table) == flagged).all() and flagged.any() and (~flagged).any()
    assert list(table["rate_reason"]) == list(why) and (table.loc[~flagged, "rate_reason"] == "").all()
    traj = pd.DataFrame({"t_s": np.r_[0.0, steps["t_peak_s"].to_numpy()]})  # a start row, then one row per step
    add_rate_reasons(traj, steps, leading_rows=1)
    assert pd.isna(traj["rate_reason"].iloc[0]) and list(traj["rate_reason"].iloc[1:]) == list(why)
    plain = get_detector(FLOORED).detect(walk).steps_  # at its own 50 Hz: nothing flagged, no column
    out = plain.copy()
    assert not add_rate_reasons(out).any() and "rate_reason" not in out.columns
    with pytest.raises(ValueError, match="leading rows"):
        add_rate_reasons(traj.iloc[:3].copy(), steps)


def test_the_warning_names_the_rate_the_floor_and_the_fix():
    below = {"detector": "single-peak", "recorded_hz": 20.0, "floor_hz": 50.0, "below": True, "stretches_below": []}
    line = rate_warning(below)
    assert "20 Hz" in line and "50 Hz" in line and "--detector adaptive" in line and "\n" not in line
    # below adaptive's own floor too: the fix is to record faster
    slow = {**below, "recorded_hz": 6.0}
    assert "--detector adaptive" not in rate_warning(slow) and "record at 50 Hz or more" in rate_warning(slow)
    own = {"detector": "adaptive", "recorded_hz": 6.0, "floor_hz": 10.0, "below": True, "stretches_below": []}
    assert "--detector adaptive" not in rate_warning(own) and "record at 10 Hz or more" in rate_warning(own)
    assert rate_warning({**below, "below": False}) is None and rate_warning(None) is None


# ---- the commands


def test_steps_cli_flags_below_the_floor_in_the_table_the_json_and_one_stderr_line(files, tmp_path, capsys):
    out = tmp_path / "steps.csv"
    assert main(["steps", str(files[20.0]), "--detector", FLOORED, "--json", "--out", str(out)]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert d["rate_check"]["below"] is True and d["rate_check"]["floor_hz"] == 50.0 and d["rate_check"]["recorded_hz"] == 20.0
    assert d["rate_check"]["n_steps_below"] == d["n_steps"] > 0
    assert all(s["rate_reason"].startswith("rate: recorded at 20 Hz") for s in d["steps"])
    lines = _warn_lines(cap.err)
    assert len(lines) == 1 and lines[0].startswith("gaitml: warning:") and "20 Hz" in lines[0] and "--detector adaptive" in lines[0]
    t = pd.read_csv(out)
    assert len(t) == d["n_steps"] and t["rate_reason"].str.startswith("rate: recorded at 20 Hz").all()
    # the text summary says it too, with the same single stderr line
    assert main(["steps", str(files[20.0]), "--detector", FLOORED]) == 0
    cap = capsys.readouterr()
    assert "rate: recorded at 20 Hz" in cap.out and len(_warn_lines(cap.err)) == 1


def test_steps_cli_at_or_above_the_floor_says_nothing(files, tmp_path, capsys):
    for path, det in ((files[50.0], FLOORED), (files[20.0], "adaptive")):
        out = tmp_path / "steps.csv"
        assert main(["steps", str(path), "--detector", det, "--json", "--out", str(out)]) == 0
        cap = capsys.readouterr()
        d = json.loads(cap.out)
        assert d["rate_check"]["below"] is False and d["rate_check"]["n_steps_below"] == 0
        assert not _warn_lines(cap.err) and not any("rate_reason" in s for s in d["steps"])
        assert "rate_reason" not in pd.read_csv(out).columns


def test_steps_cli_flags_a_slow_file_read_at_a_higher_rate(files, capsys):
    assert main(["steps", str(files[20.0]), "--detector", FLOORED, "--sampling-rate-hz", "50", "--json"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert d["sampling_rate_hz"] == 50.0 and d["rate_check"]["below"] is True and d["rate_check"]["recorded_hz"] == 20.0
    assert len(_warn_lines(cap.err)) == 1


def test_chunked_steps_flag_as_the_whole_file_does(files, monkeypatch, capsys):
    import gaitml.chunked_run as cr
    import gaitml.io.chunked as ch

    assert main(["steps", str(files[20.0]), "--detector", FLOORED, "--json"]) == 0
    whole = json.loads(capsys.readouterr().out)
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 100)
    monkeypatch.setattr(cr, "DEFAULT_CHUNK_S", 15.0)
    monkeypatch.setattr(cr, "DEFAULT_MARGIN_S", 5.0)
    assert main(["steps", str(files[20.0]), "--detector", FLOORED, "--json"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert d["chunked"] and d["rate_check"]["below"] is True and d["rate_check"]["n_steps_below"] == d["n_steps"]
    assert {k: v for k, v in d["rate_check"].items() if k not in ("n_steps", "n_steps_below")} == {
        k: v for k, v in whole["rate_check"].items() if k not in ("n_steps", "n_steps_below")
    }
    assert len(_warn_lines(cap.err)) == 1


@pytest.mark.parametrize("command", ["pdr", "segment", "label"])
def test_pdr_segment_and_label_flag_below_the_floor_and_not_above(command, files, tmp_path, capsys):
    def run(path):
        argv = [command, str(path), "--detector", FLOORED, "--json"]
        if command == "segment":
            argv += ["--out", str(tmp_path / "seg.csv")]
        if command == "pdr":
            argv += ["--out", str(tmp_path / "traj.csv")]
        if command == "label":
            (tmp_path / "iv.csv").write_text("start_s,end_s,label\n0,20,a\n20,39,b\n")
            argv += ["--intervals", str(tmp_path / "iv.csv"), "--out", str(tmp_path / "lab.csv")]
        assert main(argv) == 0
        cap = capsys.readouterr()
        return json.loads(cap.out), _warn_lines(cap.err)

    d, lines = run(files[20.0])
    assert d["rate_check"]["below"] is True and d["rate_check"]["detector"] == FLOORED and d["rate_check"]["n_steps_below"] > 0
    assert len(lines) == 1 and "20 Hz" in lines[0]
    if command == "segment":
        assert all(s["rate_reason"].startswith("rate: recorded at 20 Hz") for s in d["segments"])
        assert pd.read_csv(tmp_path / "seg.csv")["rate_reason"].notna().all()
    if command == "label":
        assert pd.read_csv(tmp_path / "lab.step-labels.csv")["rate_reason"].notna().all()
    if command == "pdr":  # the trajectory's step rows (JSON and --out), not its start row
        rows = d["trajectory"]
        assert rows[0]["rate_reason"] is None and all(r["rate_reason"].startswith("rate: recorded at 20 Hz") for r in rows[1:])
        traj = pd.read_csv(tmp_path / "traj.csv")
        assert pd.isna(traj["rate_reason"].iloc[0]) and traj["rate_reason"].iloc[1:].str.startswith("rate: recorded at 20 Hz").all()
    d, lines = run(files[50.0])
    assert d["rate_check"]["below"] is False and not lines
    if command == "segment":
        assert "rate_reason" not in pd.read_csv(tmp_path / "seg.csv").columns
    if command == "pdr":
        assert all("rate_reason" not in r for r in d["trajectory"])
        assert "rate_reason" not in pd.read_csv(tmp_path / "traj.csv").columns


@pytest.fixture(scope="module")
def still_then_walk(walk, tmp_path_factory):
    """A logger file: 50 s lying still at 20 Hz, then the walk at 50 Hz (the reader's rate change: the slow stretch
    holds no step)."""
    rng = np.random.default_rng(0)
    t0 = np.arange(0, 50, 1 / 20)
    acc0 = np.tile([0.0, 0.0, 9.81], (len(t0), 1)) + 0.02 * rng.standard_normal((len(t0), 3))
    gyr0 = 0.002 * rng.standard_normal((len(t0), 3))
    t = np.r_[t0, 50.0 + walk.t_s]
    acc, gyr = np.r_[acc0, walk.acc], np.r_[gyr0, walk.gyr]
    df = pd.DataFrame({"time_ms": 1000.0 * t})
    for i, ax in enumerate("xyz"):
        df[f"a{ax}"] = acc[:, i]
    for i, ax in enumerate("xyz"):
        df[f"g{ax}"] = gyr[:, i]
    d = tmp_path_factory.mktemp("still")
    df.to_csv(d / "logger.csv", index=False)
    (d / "iv.csv").write_text("start_s,end_s,label\n0,50,still\n50,89,walk\n")
    return d


@pytest.mark.parametrize("command", ["steps", "pdr", "segment", "label"])
def test_a_slow_stretch_without_steps_is_in_the_summary_as_on_stderr(command, still_then_walk, capsys):
    """The stderr line names a slow stretch even when it holds no step (the count there may be short); every
    command's summary says it too (pdr, segment and label used to say nothing on stdout)."""
    d = still_then_walk
    argv = [command, str(d / "logger.csv"), "--columns", "t=time_ms,acc_x=ax,acc_y=ay,acc_z=az,gyr_x=gx,gyr_y=gy,gyr_z=gz"]
    argv += ["--time-unit", "ms", "--detector", FLOORED]
    if command == "segment":
        argv += ["--out", str(d / "seg.csv")]
    if command == "label":
        argv += ["--intervals", str(d / "iv.csv"), "--out", str(d / "lab.csv")]
    assert main(argv) == 0
    cap = capsys.readouterr()
    lines = _warn_lines(cap.err)
    assert len(lines) == 1 and "0 of its" in lines[0] and "20 Hz" in lines[0]
    summary = [ln for ln in cap.out.splitlines() if WARN in ln]
    assert len(summary) == 1 and "0 of" in summary[0] and "20 Hz" in summary[0], cap.out


# ---- real recordings: the flag is set where the measured count falls


def test_tyrex_pocket_walks_are_flagged_where_single_peaks_count_falls():
    """The tyrex trouser-pocket walks of the Nexus 5 (3 people, front and back, 2 takes) taken down to 10 Hz:
    single-peak's count falls (back pocket 0.927 -> 0.352 of the motion capture's over all phones,
    experiments/reports/tyrex-steps.md) and is flagged; at 50 Hz it holds and is not; adaptive holds at 15 Hz
    and is not flagged."""
    from gaitml.io.tyrex import list_tyrex_folders, read_tyrex

    root = shared("tyrex-attitude")
    folders = [f for f in list_tyrex_folders(root) if "_Nexus5_" in f.name and f.name.endswith(("_BackPocket", "_FrontPocket"))]
    if not folders:
        pytest.skip("no tyrex Nexus 5 pocket walk in the shared data")
    counts = {k: 0 for k in ("native", "50", "10", "adaptive native", "adaptive 15")}
    for folder in folders:
        for rec in read_tyrex(folder, segments=True):
            if rec.duration_s < 10.0:  # a scrap between two gaps of the log
                continue
            assert rec.sampling_rate_hz > 100
            for key, fs, det in (("native", None, FLOORED), ("50", 50.0, FLOORED), ("10", 10.0, FLOORED)):
                steps = get_detector(det).detect(rec if fs is None else resample_recording(rec, fs)).steps_
                assert steps.attrs["rate_check"]["below"] is (key == "10")
                counts[key] += len(steps)
            for key, fs in (("adaptive native", None), ("adaptive 15", 15.0)):
                steps = get_detector("adaptive").detect(rec if fs is None else resample_recording(rec, fs)).steps_
                assert steps.attrs["rate_check"]["below"] is False
                counts[key] += len(steps)
    assert counts["native"] > 100
    assert counts["10"] < 0.7 * counts["native"]  # flagged: the count falls
    assert abs(counts["50"] - counts["native"]) < 0.05 * counts["native"]  # not flagged: it holds
    assert abs(counts["adaptive 15"] - counts["adaptive native"]) < 0.1 * counts["adaptive native"]
    assert np.isfinite(list(counts.values())).all()


def test_adaptive_refuses_a_recording_too_slow_for_its_band_naming_the_fix(walk, tmp_path, capsys):
    """At 8 Hz adaptive's 0.5-4 Hz band does not fit under half the rate (docs/steps-and-zupt.md: 'at 8 Hz or below it
    refuses the recording'): one error line that says the rate is too low and what to do, not only the parameter."""
    slow = tmp_path / "walk8.csv"
    write_gaitml_csv(resample_recording(walk, 8.0), slow)
    assert main(["steps", str(slow), "--detector", "adaptive"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "8 Hz" in err and f"record at {DETECTORS['adaptive'].rate_floor_hz:g} Hz or more" in err
