"""A step-window model marks every step of a recording made below its training rate out of domain (gaitml.models.rate_reason)."""

from __future__ import annotations

from gaitml.models import load_model, predict_step_windows, resample_recording
from gaitml.simulate import simulate_dataset


def test_every_step_of_a_low_rate_recording_is_out_of_domain_with_the_rate_reason(step_model_dir):
    model = load_model(step_model_dir / "model")
    assert model.domain.min_rate_hz == 50.0  # trained on simulated phones at 50 Hz, without rate copies
    rec = simulate_dataset(n_subjects=1, duration_s=30.0, seed=322)[0]
    native = predict_step_windows(model, rec)
    assert native.attrs["rate_check"]["below"] is False and not any(str(r).startswith("rate:") for r in native["out_of_domain_reason"])
    low = predict_step_windows(model, resample_recording(rec, 30.0))
    assert len(low) > 10 and (low["in_domain"] == False).all()  # noqa: E712 (object column)
    assert set(low["out_of_domain_reason"]) == {"rate: recorded at 30 Hz, below the 50 Hz the model was trained at"}
    assert low.attrs["rate_check"] == {"recorded_hz": 30.0, "trained_min_hz": 50.0, "tolerance": 0.9, "below": True}
