"""Output options: an empty name is refused (it once wrote nothing and exited 0), and a refused study leaves
no folder of its own behind."""

from __future__ import annotations

import pytest

from wheelrail.cli.dispatch import main


def _main(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


@pytest.mark.parametrize(
    "argv",
    [
        ["run", "--set", "corrugated-rail", "--length-m", "0.1", "--out", ""],
        ["run", "--set", "corrugated-rail", "--length-m", "0.1", "--out", "  "],
        ["study", "filters", "--set", "corrugated-rail", "--out", ""],
        ["track", "--csv", ""],
        ["track", "--plot", ""],
        ["filters", "--csv", ""],
    ],
    ids=["run --out ''", "run --out blank", "study --out ''", "track --csv ''", "track --plot ''", "filters --csv"],
)
def test_an_empty_output_name_is_refused_before_anything_runs(capsys, tmp_path, monkeypatch, argv):
    monkeypatch.chdir(tmp_path)
    code, out, err = _main(capsys, *argv)
    assert code != 0 and out == "" and err.count("\n") == 1 and "empty" in err, err
    assert list(tmp_path.iterdir()) == []


def test_a_refused_study_leaves_no_empty_output_folder(capsys, tmp_path):
    out = tmp_path / "new" / "study"
    code, _, err = _main(capsys, "study", "filters", "--set", str(tmp_path / "missing.csv"), "--out", str(out))
    assert code != 0 and "missing.csv" in err
    assert list(tmp_path.iterdir()) == []  # neither study nor its parent new/, both made by the study
    # an existing folder, and what is in it, stays
    out.mkdir(parents=True)
    (out / "notes.txt").write_text("mine")
    code, _, _ = _main(capsys, "study", "filters", "--set", str(tmp_path / "missing.csv"), "--out", str(out))
    assert code != 0 and (out / "notes.txt").read_text() == "mine"
