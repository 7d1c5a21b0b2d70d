"""README's example runs as written, at smaller sizes (fewer presses and epochs): the API it shows is real."""

import pathlib
import re

import pytest

from ._smaller import smaller

README = pathlib.Path(__file__).resolve().parents[1] / "README.md"

#: What the test shrinks so that the example runs in seconds; each must be in the example.
SMALLER = {
    'n_per_class=20, random_state=0': 'n_per_class=6, image_size=(48, 64), random_state=0',
    'max_epochs=50': 'max_epochs=2',
    'n_samples=50': 'n_samples=4',
    'make_named_pipeline("convlstm"), "variance"': 'make_named_pipeline("convlstm", max_epochs=2), "variance"',
    'range(5)': 'range(2)',
}


@pytest.mark.slow
@pytest.mark.torch_threads(1)
def test_readme_example_runs():
    code = re.search(r"```python\n(.*?)```", README.read_text(), re.S).group(1)
    code = smaller(code, SMALLER, "README's example (tests/test_readme_example.py)")
    namespace = {}
    exec(compile(code, str(README), "exec"), namespace)
    assert namespace["proba"].shape == (4, 5, 5)
    assert len(namespace["learner"].classes_) == 5
