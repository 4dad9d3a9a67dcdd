"""Tests of the shared table and report layer (``ndlfd.jobs._report``)."""

from __future__ import annotations

import math

import pytest

from ndlfd._errors import ValidationError
from ndlfd.jobs._report import Report, fmt_number, image, markdown, markdown_table


# ------------------------------------------------------------------ tables
def test_table_left_aligned_by_default():
    text = markdown_table(["figure", "paper", "ours"], [["Fig. 3", 17, "4 / 11"]])
    assert text == (
        "| figure | paper | ours |\n"  # keep one line per row
        "|---|---|---|\n"
        "| Fig. 3 | 17 | 4 / 11 |"
    )


def test_table_right_aligns_numeric_columns():
    text = markdown_table(
        ["generator", "DTW", "failed"],
        [["ndlfd", "0.0124 (0.0117)", "0/4"], ["mean", "0", "1/4"]],
        align="lrr",
    )
    assert text == (
        "| generator | DTW | failed |\n"
        "|---|---:|---:|\n"
        "| ndlfd | 0.0124 (0.0117) | 0/4 |\n"
        "| mean | 0 | 1/4 |"
    )


def test_table_without_rows_is_header_and_rule():
    assert markdown_table(["a", "b"], []) == "| a | b |\n|---|---|"
    assert markdown_table(["a", "b"], iter([])) == "| a | b |\n|---|---|"


def test_table_escapes_pipes_and_line_breaks_and_keeps_empty_cells():
    text = markdown_table(["what", "note"], [["|det A|", "two\nlines"], ["x", ""]])
    assert text.splitlines()[2:] == [r"| \|det A\| | two lines |", "| x |  |"]


@pytest.mark.parametrize(
    ("align", "got"),
    [("l", "'l'"), ("lrc", "'lrc'"), ("lx", "'lx'")],
)
def test_table_align_must_name_each_column(align, got):
    with pytest.raises(ValidationError, match=f"one letter 'l' or 'r' .* got {got}"):
        markdown_table(["a", "b"], [], align=align)


def test_table_rows_must_have_one_cell_per_column():
    with pytest.raises(ValidationError, match=r"2 cells .* got 3: \['x', 'y', 'z'\]"):
        markdown_table(["a", "b"], [["x", "y", "z"]])


# ------------------------------------------------------------- formatting
def test_fmt_number():
    assert fmt_number(0.012345) == "0.0123"
    assert fmt_number(1.31e-16) == "1.31e-16"
    assert fmt_number(0.0) == "0"
    assert fmt_number(None) == fmt_number(math.nan) == "–"
    assert fmt_number(math.inf) == "inf"
    assert fmt_number(7.899, ".2f") == "7.90"


def test_markdown_joins_blocks_with_one_blank_line():
    blocks = ["# T", "", "para", markdown_table(["a"], [[1]]), image("f.png", "F")]
    assert markdown(blocks) == "# T\n\npara\n\n| a |\n|---|\n| 1 |\n\n![F](f.png)\n"
    assert markdown([]) == "\n"


# ------------------------------------------------------------------ folder
def _leftovers(folder):
    return sorted(p.name for p in folder.rglob("*") if p.name.endswith(".tmp"))


def test_report_writes_markdown_and_records_files(tmp_path):
    report = Report(tmp_path / "a" / "b")
    path = report.write("summary.md", ["# Title", "Text."])
    assert path == tmp_path / "a" / "b" / "summary.md"
    assert path.read_text(encoding="utf-8") == "# Title\n\nText.\n"
    assert report.files == [path]


def test_report_leaves_no_file_when_the_blocks_fail(tmp_path):
    def blocks():
        yield "# Title"
        raise RuntimeError("a section failed")

    report = Report(tmp_path)
    (tmp_path / "report.md").write_text("old", encoding="utf-8")
    with pytest.raises(RuntimeError, match="a section failed"):
        report.write("report.md", blocks())
    assert (tmp_path / "report.md").read_text(encoding="utf-8") == "old"
    assert _leftovers(tmp_path) == [] and report.files == []


def test_report_leaves_no_partial_file_when_writing_fails(tmp_path):
    report = Report(tmp_path)
    text = "x" * 100_000 + "\ud800"  # a lone surrogate: UTF-8 fails mid-file
    with pytest.raises(UnicodeEncodeError):
        report.write("report.md", [text])
    assert list(tmp_path.iterdir()) == []


def test_report_saves_figures_atomically(tmp_path):
    pytest.importorskip("matplotlib")
    from ndlfd.plot import new_figure

    report = Report(tmp_path, dpi=20)
    fig, _ = new_figure(1, size=(2, 2))
    path = report.figure(fig, "shapes/Line.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert report.files == [tmp_path / "shapes" / "Line.png"]

    class Broken:
        def savefig(self, fname, **kw):
            fname.write_bytes(b"\x89PNG half")
            raise OSError("disk full")

    with pytest.raises(OSError, match="disk full"):
        report.figure(Broken(), "broken.png")
    assert not (tmp_path / "broken.png").exists()
    assert _leftovers(tmp_path) == [] and len(report.files) == 1


def test_report_folder_must_be_a_folder(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(OSError):
        Report(tmp_path / "file")
