"""A pass-by's train: its length, axle count and axles per metre have accepted ranges, worded per front end."""

from __future__ import annotations

import pytest

from wheelrail.cli.commands._common import CLI_NAMES
from wheelrail.core.errors import WheelrailError
from wheelrail.core.noise.run_noise import checked_train


@pytest.mark.parametrize(
    ("axles", "length", "parameter"),
    [
        (40, 1e300, "train_length"),  # once a pass-by of -2 880.9 dB(A)
        (40, 1e-300, "train_length"),  # once 105.4 dB(A)
        (40, 2.5, "train_axles"),  # one axle every 6 cm
        (10**6, 200.0, "train_axles"),
        (0, 200.0, "train_axles"),
        (40, float("nan"), "train_length"),
    ],
)
def test_impossible_trains_are_refused(axles, length, parameter):
    with pytest.raises(WheelrailError) as error:
        checked_train(axles, length)
    assert error.value.parameter == parameter
    assert "\n" not in error.value.render(CLI_NAMES)


def test_the_dense_train_names_its_most_axles_in_the_command_lines_words():
    with pytest.raises(WheelrailError) as error:
        checked_train(40, 2.5)
    text = error.value.render(CLI_NAMES)
    assert text.startswith("--train-axles 40") and "at most 3" in text and "2.5 m train" in text, text


@pytest.mark.parametrize(("axles", "length"), [(40, 200.0), (1, 2.0), (4, 3.0), (2000, 5000.0), (16, 80.0)])
def test_real_trains_pass(axles, length):
    assert checked_train(axles, length) == (axles, length)
