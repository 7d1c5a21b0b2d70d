"""The vendored copy of scikit-learn's parameter validation (``sklearn_hardness/utils/_param_validation.py``).

Its licence travels with the wheel. (tests/test_param_validation_parity.py checks that it behaves like the
installed scikit-learn's.)
"""

import pathlib
import re
import textwrap

from sklearn_hardness.utils import _param_validation

ROOT = pathlib.Path(__file__).resolve().parents[1]
NOTICE = "LICENSES/scikit-learn.txt"


def _bsd_text(text):
    """The BSD 3-Clause licence in ``text``, from its title to its last sentence."""
    found = re.search(r"^( *)BSD 3-Clause License\n.*?OF THIS SOFTWARE, EVEN IF ADVISED OF THE POSSIBILITY OF SUCH "
                      r"DAMAGE\.", text, re.S | re.M)
    assert found, "no BSD 3-Clause licence text found"
    return textwrap.dedent(found.group(0))


def test_the_wheel_carries_scikit_learn_s_licence_for_the_vendored_code():
    pyproject = (ROOT / "pyproject.toml").read_text()
    files = re.search(r"^license-files = \[(.*?)\]", pyproject, re.M).group(1)
    assert re.findall(r'"([^"]+)"', files) == ["LICENSE", NOTICE]
    notice = (ROOT / NOTICE).read_text()
    assert "Copyright (c) 2007-2026 The scikit-learn developers." in notice
    assert "sklearn_hardness/utils/_param_validation.py" in notice
    assert NOTICE in (ROOT / "LICENSE").read_text()  # our licence points to it
    # the notice the module carries is the one the wheel carries
    assert _bsd_text(_param_validation.__doc__) == _bsd_text(notice)
