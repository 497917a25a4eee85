"""scikit-learn's estimator checks over the linear OVO SVM and the torch baselines.

The torch instances are small (one hidden layer of 16, 8 filters, 20 epochs at
learning rate 0.01) so that the whole check suite stays short, yet they clear the
accuracy bar of ``check_classifiers_train``.
Checks that cannot pass for a stated reason are listed in :data:`EXPECTED_FAILED`
(scikit-learn's ``expected_failed_checks`` convention: they run and are
reported as xfail, so a check that starts passing shows up as XPASS).
"""

from __future__ import annotations

import pytest
from sklearn.utils.estimator_checks import parametrize_with_checks

from gaitml.models import LinearOVOSVM, TorchCNN1DClassifier, TorchMLPClassifier, torch_available

#: estimator class -> {check name: reason it is expected to fail}. None is needed at
#: present: every check runs and passes (the dict stays as the place to list one, with its reason).
EXPECTED_FAILED: dict[type, dict[str, str]] = {
    LinearOVOSVM: {},
    TorchMLPClassifier: {},
    TorchCNN1DClassifier: {},
}


def _expected_failed(estimator) -> dict[str, str]:
    return EXPECTED_FAILED[type(estimator)]


ESTIMATORS = [LinearOVOSVM()]
if torch_available():
    ESTIMATORS += [
        TorchMLPClassifier(hidden=(16,), epochs=20, batch_size=32, learning_rate=1e-2),
        TorchCNN1DClassifier(channels=(8, 8), kernel_size=3, epochs=20, batch_size=32, learning_rate=1e-2),
    ]


@parametrize_with_checks(ESTIMATORS, expected_failed_checks=_expected_failed)
def test_sklearn_estimator_checks(estimator, check):
    check(estimator)


def test_torch_estimators_are_checked():
    if not torch_available():
        pytest.skip("torch extra not installed: TorchMLPClassifier and TorchCNN1DClassifier are not checked")
    assert {type(e) for e in ESTIMATORS} == {LinearOVOSVM, TorchMLPClassifier, TorchCNN1DClassifier}
