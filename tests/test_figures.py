"""Every figure README, ``studies/`` and the docs quote is found in the output the page names for it.

The rules (what a figure is, how a page names its outputs, which differences of
writing count as the same number) are :mod:`harness.figures`' docstring and
``studies/README.md``; the tests below read the real pages, then pin each rule on
small pages of their own, each with a figure the rule must catch.
"""

import os

import pytest

from harness.figures import OUTPUTS, check_page, check_pages, find_figures, missing_header, pages, read_units


def test_every_figure_of_readme_studies_and_docs_is_found_in_its_outputs():
    problems = check_pages()
    assert not problems, f"{len(problems)} figure(s) not found:\n" + "\n".join(problems)


def test_the_pages_checked_are_readme_the_studies_and_the_docs():
    checked = set(pages())
    assert {"README.md", "studies/README.md", "docs/simulator.md", "docs/getting_started.rst"} <= checked
    assert {f"studies/pages/{name}" for name in os.listdir(os.path.join(OUTPUTS, "..", "pages"))} <= checked
    assert any(path.startswith("docs/user_guide/") for path in checked)


@pytest.mark.parametrize("name", sorted(n for n in os.listdir(OUTPUTS) if not n.endswith(".provenance")))
def test_every_output_names_its_command_commit_and_date(name):
    # in its first lines, or in the sidecar NAME.provenance where the file cannot hold them
    assert missing_header(os.path.join(OUTPUTS, name)) == []


def test_every_sidecar_stands_beside_an_output():
    for name in os.listdir(OUTPUTS):
        if name.endswith(".provenance"):
            assert os.path.isfile(os.path.join(OUTPUTS, name[: -len(".provenance")])), name


# --- the rules, each on a page of its own ---------------------------------------------------------


@pytest.fixture
def folder(tmp_path):
    """A page folder and an outputs folder, with ``write(name, text)`` for either."""
    outputs = tmp_path / "outputs"
    outputs.mkdir()
    (outputs / "run.txt").write_text(
        "# command: python s.py\n# commit: 0123456789, 2026-01-01T00:00Z\n"
        "pipeline  bal. accuracy [95% CI]\n"
        "peak      0.5896 [0.391, 0.722]\n"
        "thompson  accuracy %  296 (296 pairs)  85.1 [82.0, 88.3]  +5.1 [2.1, 8.2]  -3.5 [-4.2, -2.8]\n"
        "share     0.637\n"
        "count     49 (49 pairs)\n"
    )

    def check(page, suffix=".md"):
        path = tmp_path / f"page{suffix}"
        path.write_text(page)
        return check_page(str(path), outputs=str(outputs))

    return check


def test_a_figure_written_as_in_its_output_or_rounded_is_found(folder):
    assert folder("`run.txt`: 0.5896 and 0.590 and 0.59 and 0.6\n") == []
    # the other way round, or another number, is not
    assert len(folder("`run.txt`: 0.58963 and 0.58\n")) == 2


def test_an_interval_is_found_only_with_its_estimate_and_ends_in_order_on_one_line(folder):
    assert folder("`run.txt`: +5.1 [+2.1, +8.2] points, 0.59 [0.39, 0.72], 85.1% [82.0, 88.3]\n") == []
    problems = folder("`run.txt`: +5.1 [+2.1, +8.3] and +5.1 [+8.2, +2.1] and 0.59 [0.39, 82.0]\n")
    assert len(problems) == 3


def test_a_sign_is_the_output_s_or_dropped_in_prose(folder):
    assert folder("`run.txt`: +5.1 and 5.1; -3.5 [-4.2, -2.8]; settles 3.5 presses sooner\n") == []
    assert len(folder("`run.txt`: -5.1 and +3.5 [+4.2, +2.8]\n")) == 2


def test_a_share_may_be_written_as_a_percent_and_a_level_is_not_a_figure(folder):
    assert folder("`run.txt`: 63.7% of the runs, 64% too, with a 95% paired t-interval\n") == []
    assert len(folder("`run.txt`: 63.8%\n")) == 1


def test_the_count_of_a_paired_run_s_pairs_is_checked(folder):
    assert folder("`run.txt`: 296 of 300 pairs; 49 pairs\n") == []
    # the slip of issue 62: README said 50 pairs where the output has 49
    assert folder("`run.txt`: -3.5 [-4.2, -2.8] (50 pairs)\n") == ["page.md:1: 50 pairs not found (run.txt)"]


def test_a_figure_is_looked_up_only_in_the_outputs_its_unit_names(folder, tmp_path):
    (tmp_path / "outputs" / "other.txt").write_text("# command: x\n# commit: abcdef0, 2026-01-01\n0.77\n")
    page = (
        "First paragraph, `run.txt`: 0.59.\n\n"
        "Second paragraph names none: 0.59.\n\n"
        "Third, `other.txt`: 0.59 and 0.77.\n\n"
        "<!-- outputs: other.txt -->\nFourth, by a marker: 0.77.\n\n"
        "Fifth names `missing.txt`.\n"
    )
    problems = folder(page)
    assert problems == [
        "page.md:3: 0.59 not found (no output named)",
        "page.md:5: 0.59 not found (other.txt)",
    ]  # missing.txt is no output: a name that is not in the folder is text


def test_a_table_s_rows_take_the_outputs_of_the_paragraph_above_it_and_their_own(folder, tmp_path):
    (tmp_path / "outputs" / "other.txt").write_text("# command: x\n# commit: abcdef0, 2026-01-01\n0.77\n")
    page = (
        "The table is from `run.txt`:\n\n"
        "| pipeline | score |\n|---|---|\n| peak | 0.59 |\n| other | 0.77 `other.txt` |\n| wrong | 0.77 |\n"
    )
    assert folder(page) == ["page.md:7: 0.77 not found (run.txt)"]


def test_section_outputs_hold_until_the_next_heading(folder):
    page = "## A\n\n<!-- section outputs: run.txt -->\n\nOne: 0.59.\n\nTwo: 0.637.\n\n## B\n\nThree: 0.59.\n"
    assert folder(page) == ["page.md:11: 0.59 not found (no output named)"]


def test_a_derived_figure_is_computed_from_figures_of_the_outputs(folder):
    ok = ("`run.txt`: a margin of 0.05 <!-- derived: 0.05 = 0.637 - 0.5896 -->, a mean 0.61\n"
          "<!-- derived: 0.61 = mean(0.637, 0.5896) -->\n")
    assert folder(ok) == []
    wrong = "`run.txt`: a margin of 0.06 <!-- derived: 0.06 = 0.637 - 0.5896 -->\n"
    assert folder(wrong) == ["page.md:1: 0.06 = 0.637 - 0.5896 gives 0.0474"]
    unfounded = "`run.txt`: 0.10 <!-- derived: 0.10 = 0.73 - 0.63 -->\n"
    assert folder(unfounded) == ["page.md:1: the operand 0.73 of 0.10 = 0.73 - 0.63 is in none of its outputs"]


def test_a_given_figure_needs_its_reason(folder):
    assert folder("<!-- given: 0.70 [-1, 1]: the issue's target and a range -->\nTarget 0.70 in [-1, 1].\n") == []
    with pytest.raises(ValueError, match="reason"):
        folder("<!-- given: 0.70 -->\nTarget 0.70.\n")


def test_code_comments_links_and_versions_are_not_figures():
    text = "`lr=0.3` run [x](outputs/0.5.txt) on torch 2.13, Python >= 3.10, openblas 0.3.15, in 3-12 presses"
    stripped = read_units(text)[0].text
    assert [f.text for f in find_figures(stripped)] == []


def test_a_text_fence_quotes_an_output_and_is_checked(folder):
    page = "From `run.txt`:\n\n```text\npeak 0.5896\nshare 0.638\n```\n\n```bash\npython s.py --lr 0.25\n```\n"
    assert folder(page) == ["page.md:5: 0.638 not found (run.txt)"]


def test_restructured_text_pages_are_read_with_their_comment_markers(folder):
    page = (
        "Title\n=====\n\n.. outputs: run.txt\n\nIt scored 0.59 (``--lr 0.25``) and\n:math:`0.33` here::\n\n"
        "    code 0.44\n\n.. given: 0.2: the paper's setting\n\nDropout 0.2, not 0.3.\n"
    )
    assert folder(page, suffix=".rst") == ["page.rst:13: 0.3 not found (no output named)"]


def test_readme_s_quick_table_is_the_harness_s_to_write_not_this_check_s(folder):
    from harness.readme_table import END, START

    assert folder(f"{START}\n```\nentropy 86.67% +- 9.43%\n```\n{END}\n") == []


def test_an_output_without_its_header_is_reported_and_a_sidecar_supplies_it(tmp_path):
    table = tmp_path / "t.csv"
    table.write_text("a,b\n1,2\n")
    assert missing_header(str(table)) == ["command", "commit", "date"]
    (tmp_path / "t.csv.provenance").write_text("# command: python b.py --out t\n# commit: 0123abc, 2026-01-02\n")
    assert missing_header(str(table)) == []
    copy = tmp_path / "stats.md"
    copy.write_text("statistics\n")
    (tmp_path / "stats.md.provenance").write_text("# external: a copy\n# command: their run, 2026-01-03\n")
    assert missing_header(str(copy)) == []  # a source not run here has no commit of ours
