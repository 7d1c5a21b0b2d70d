"""Every figure a page quotes, found in the output file the page names for it.

    python -m harness.figures              # README, studies/, docs: list what is not found
    python -m harness.figures PAGE ...     # these pages only

A *figure* is a number with a decimal point (``0.59``, ``+5.1``), a number with
a percent sign (``48%``, ``63.7%``), an interval (``[-3.1, +13.5]``, integer ends
and ``never`` included) with the estimate written just before it, or the count
of a paired run's pairs (``296 pairs``, ``296 of 300 pairs``: 20 or more; the
9 Wedge pairs are pairs of objects). Integers elsewhere (seeds, counts of
objects, seconds) are not figures. Not read: code (fences, indented code, ``inline code``),
HTML comments, link targets, version numbers (``torch 2.13``, ``0.3.15``) and
the block between README's quick-table markers (:mod:`harness.readme_table`
writes it from its command).

A page is read in *units*: a paragraph, a list item or a table row. A unit's
figures are looked up in the output files it names (a file name of
``studies/outputs/`` in the unit, as text, code or link), in those named by
the paragraph just before its table or list, and in those of a marker:

- ``<!-- outputs: a.txt b.txt -->`` (reStructuredText: ``.. outputs: a.txt``)
  names outputs. On a line of its own it holds for the next paragraph, table or
  list; inside a unit, for that unit.
- ``<!-- derived: 0.05 = 0.607 - 0.557; ... -->``: a figure computed from
  others; every number with a decimal point in the expression is looked up as
  a figure of the unit, and the expression must round to the figure.
- ``<!-- given: 0.70 +0.10: the issue's targets -->``: figures that are inputs
  (targets, settings, a paper's published numbers), each with its reason.

A figure is found where an output holds the same number, allowing only these
differences of writing: rounding (the page's ``0.59`` for ``0.5896`` or
``0.590``; never the other way), a ``+`` or no sign for a positive number, no
sign in prose for a negative one (``3.5 presses sooner`` for ``-3.5``), and a
share written as a percent (``63.7%`` for ``0.637``, ``59%`` for ``59.0``). An
interval is found only with its estimate and both ends, in this order, on one
line of an output.
"""

from __future__ import annotations

import ast
import glob
import operator
import os
import re
from dataclasses import dataclass, field

from . import ROOT

__all__ = ["OUTPUTS", "PAGES", "Figure", "Unit", "read_units", "find_figures", "check_page", "check_pages",
           "pages", "missing_header", "main"]

#: The folder of the outputs.
OUTPUTS = os.path.join(ROOT, "studies", "outputs")
#: The pages whose figures are checked (globs, from the repository root).
PAGES = ("README.md", "studies/README.md", "studies/pages/*.md", "docs/simulator.md", "docs/getting_started.rst",
         "docs/user_guide/*.rst")

_NUM = r"[+\-]?(?:\d+\.\d+|\d+)"
_END = rf"(?:{_NUM}|never)"
# an estimate (optional) and its interval; a sign only where no digit or word is just before it
_INTERVAL = re.compile(rf"(?:(?<![\w.])({_NUM})(%?)(?:\s*(?:points|presses|s|pp))?\s*)?"
                       rf"\[\s*({_END})%?\s*,\s*({_END})%?\s*\]")
_SINGLE = re.compile(r"(?:(?<![\w.])([+\-]))?(?<![\w.])(\d+\.\d+|\d+(?=%))(%?)(?![\w]|\.\d)")
_PAIRS = re.compile(r"(?<![\w.])(\d+)(?: of \d+)? pairs\b(?! of)")
_VERSION_BEFORE = re.compile(r"(?:Python|torch|numpy|scipy|scikit-learn|skorch|OpenBLAS|openblas|version|CUDA|"
                             r"Eq\.|Equation|Section|Sec\.|Table|Figure|Fig\.|\bv)\s*(?:>=|<=|==|>|<)?\s*$")
_OUT_NUM = re.compile(r"(?<![\w.])([+\-]?)(\d+\.\d*|\d+)(?:e([+\-]?\d+))?(%?)|\b(never)\b")
_MARKER = re.compile(r"<!--\s*(section outputs|section given|outputs|derived|given)\s*:(.*?)-->", re.S)
_RST_MARKER = re.compile(r"^\.\.\s+(outputs|derived|given)\s*:(.*)$")
_RST_CODE = {"code-block", "code", "sourcecode", "math", "literalinclude", "testcode", "testoutput", "doctest",
             "plot", "highlight"}
_OUTPUT_NAME = re.compile(r"[\w.\-]+\.(?:txt|csv|png|md)\b")
# a confidence level is a setting, not a figure: "95% interval", "95% paired t-interval", "95% CI"
_LEVEL = re.compile(r"(?:80|90|95|99)%(?=\s+(?:[\w-]+\s+){0,3}?(?:t-)?(?:intervals?|CI|confidence|bootstrap)\b)")


@dataclass
class Figure:
    """One figure of a page: its text, where it is, and the numbers it is made of."""

    text: str
    line: int
    numbers: list  # (sign, digits, percent) of the estimate (if any) and the ends, or of the one number
    interval: bool = False
    pairs: bool = False


@dataclass
class Unit:
    """A paragraph, list item or table row, with the outputs and declarations that hold for it."""

    text: str
    line: int
    outputs: set = field(default_factory=set)
    derived: list = field(default_factory=list)
    given: dict = field(default_factory=dict)


# --- reading pages -------------------------------------------------------------------------------


def _strip(text, rst):
    """Text with code, comments and link targets blanked out (line breaks kept)."""
    text = re.sub(r"<!--.*?-->", lambda m: re.sub(r"[^\n]", " ", m.group()), text, flags=re.S)
    if rst:
        text = re.sub(r":math:`[^`]*`|``[^`]*``|<[^>\s]*>`_", " ", text)
    else:
        text = re.sub(r"`[^`]*`", lambda m: re.sub(r"[^\n]", " ", m.group()), text)
        text = re.sub(r"\]\([^)\s]*\)", "]", text)
    return text


def _expand(text):
    """Names written with braces, ``x_seed{0..2}.txt`` or ``x_{table,paired}{,_rerun}.txt``, one by one."""
    def expand(token):
        m = re.search(r"\{(\d+\.\.\d+|[\w,\-]*,[\w,\-]*)\}", token)
        if not m:
            return [token]
        body = m.group(1)
        if ".." in body:
            first, last = body.split("..")
            items = [str(i) for i in range(int(first), int(last) + 1)]
        else:
            items = body.split(",")
        return [name for item in items for name in expand(token[:m.start()] + item + token[m.end():])]

    return re.sub(r"[\w.\-]*\{[\w.,\-{}]*\}[\w.\-{},]*", lambda m: " ".join(expand(m.group())), text)


def _output_names(text, outputs):
    names = set()
    for name in _OUTPUT_NAME.findall(_expand(text)):
        if os.path.isfile(os.path.join(outputs, name)):
            names.add(name)
    return names


def _markers(text, rst=False):
    code = r"``[^`]*``" if rst else r"`[^`]*`"
    found = [(kind, body.strip()) for kind, body in _MARKER.findall(re.sub(code, " ", text))]  # not in code
    if rst:
        found += [(m.group(1), m.group(2).strip()) for m in map(_RST_MARKER.match, text.splitlines()) if m]
    return found


def _apply(unit, markers):
    for kind, body in markers:
        if kind in ("outputs", "section outputs"):
            names = _expand(body).replace(",", " ").split()
            unit.outputs |= {os.path.basename(name) for name in names}
        elif kind == "section given":
            if not body.strip():
                raise ValueError(f"line {unit.line}: a section given needs its reason.")
            unit.given["*"] = body.strip()
        elif kind == "derived":
            for part in filter(None, (p.strip() for p in body.split(";"))):
                figure, _, expression = part.partition("=")
                unit.derived.append((figure.strip(), expression.strip()))
        else:
            figures, sep, reason = body.partition(":")
            if not sep or not reason.strip():
                raise ValueError(f"line {unit.line}: a given figure needs its reason after ':', got {body!r}.")
            for token in re.findall(r"\[[^\]]*\]|[^\s\[\]]+", figures):
                for figure in find_figures(token) or [Figure(token, 0, [])]:
                    unit.given[figure.text] = reason.strip()


def _blocks(lines, rst):
    """(first line number, lines) of the blocks outside code (``text`` fences are read), split at blank lines."""
    blocks, current, start = [], [], 0
    fence = indented = quoted = False
    for i, line in enumerate(lines, 1):
        stripped = line.strip()
        if not rst and stripped.startswith("```"):
            fence = not fence
            current and blocks.append((start, current))
            current, quoted = [], fence and stripped[3:].strip() == "text"
            continue
        if fence:
            if quoted:  # a ```text block quotes an output: each line read as a table row
                start = start if current else i
                current.append(f"| {line} |")
            continue
        if rst:
            if indented:
                if stripped and not line[:1].isspace():
                    indented = False
                else:
                    current and blocks.append((start, current))
                    current = []
                    continue
            if stripped.startswith((">>>", "...")):
                continue
            directive = re.match(r"\.\.\s+([\w-]+)::", stripped)
            if directive and directive.group(1) in _RST_CODE:
                indented = True
                continue
            if stripped.endswith("::") and not directive:
                indented = True
                line = line.rstrip()[:-1]
        elif line.startswith("    ") and not current and not re.match(r"\s*([-*]|\d+\.)\s", line):
            continue  # an indented code block
        if not stripped:
            current and blocks.append((start, current))
            current = []
            continue
        if not current:
            start = i
        current.append(line)
    current and blocks.append((start, current))
    return blocks


def _units_of(start, block):
    """Table rows and list items each one unit, a paragraph one unit."""
    if block[0].lstrip().startswith("|"):
        return [(start + k, [row]) for k, row in enumerate(block)
                if not re.fullmatch(r"\s*\|[\s:|\-]*\|\s*", row)]
    if re.match(r"\s*([-*]|\d+\.)\s", block[0]):
        items = []
        for k, row in enumerate(block):
            if re.match(r"\s*([-*]|\d+\.)\s", row) and (not items or not row.startswith("  ")):
                items.append((start + k, [row]))
            else:
                items[-1][1].append(row)
        return items
    return [(start, block)]


def _quick_table(text):
    """README's quick table (written by :mod:`harness.readme_table`) blanked out."""
    from .readme_table import END, START

    begin, end = text.find(START), text.find(END)
    if begin < 0 or end < begin:
        return text
    return text[:begin] + re.sub(r"[^\n]", " ", text[begin:end]) + text[end:]


def _leading_comments(block, rst):
    """How many of the block's first lines are whole comments (markers)."""
    n, inside = 0, False
    for line in block:
        stripped = line.strip()
        if rst:
            if not _RST_MARKER.match(stripped):
                break
            n += 1
            continue
        if not inside and not stripped.startswith("<!--"):
            break
        inside = "-->" not in stripped or stripped.rfind("<!--") > stripped.rfind("-->")
        if not inside and not stripped.endswith("-->"):
            break  # text after the comment on the same line: part of the paragraph
        n += 1
    return 0 if inside else n


def read_units(text, rst=False, outputs=OUTPUTS):
    """The units of a page's ``text``, with their outputs, derived and given figures.

    Parameters
    ----------
    text : str
        A Markdown page (or reStructuredText with ``rst=True``).
    rst : bool, default=False
        Whether the page is reStructuredText.
    outputs : str, default=OUTPUTS
        The folder whose files a page names.

    Returns
    -------
    units : list of Unit

    Examples
    --------
    >>> from harness.figures import read_units
    >>> [(u.line, sorted(u.outputs)) for u in read_units("a `reproduce_quick.txt` b\\n\\n| x |\\n|---|\\n| 0.5 |")]
    [(1, ['reproduce_quick.txt']), (3, ['reproduce_quick.txt']), (5, ['reproduce_quick.txt'])]
    """
    text = _quick_table(text)
    lines = text.splitlines()
    units, pending, lead, section = [], [], set(), []
    for start, block in _blocks(lines, rst):
        if block[0].startswith("#"):
            section = []  # a heading ends the section's outputs
        head = _leading_comments(block, rst)
        if head and head < len(block):  # comment lines just above a table or paragraph: for all of it
            pending += _markers("\n".join(block[:head]), rst)
            start, block = start + head, block[head:]
        raw = "\n".join(block)
        own = _markers(raw, rst)
        if re.fullmatch(r"\s*(<!--.*?-->\s*)+", raw, flags=re.S) or (
                rst and all(_RST_MARKER.match(line.strip()) for line in block)):
            pending += own  # a marker on its own: for the next block
            continue
        is_group = block[0].lstrip().startswith("|") or re.match(r"\s*([-*]|\d+\.)\s", block[0])
        for line, rows in _units_of(start, block):
            unit_text = "\n".join(rows)
            unit = Unit(_strip(unit_text, rst), line, outputs=_output_names(unit_text, outputs))
            if is_group:
                unit.outputs |= lead
            _apply(unit, section + pending + (_markers(unit_text, rst) if is_group else own))
            units.append(unit)
        section += [(kind, body) for kind, body in pending + own if kind.startswith("section ")]
        pending = []
        if not is_group:
            lead = _output_names(raw, outputs) | {name for u in units[-1:] for name in u.outputs}
    return units


def find_figures(text):
    """The figures of a unit's text, in reading order.

    Examples
    --------
    >>> from harness.figures import find_figures
    >>> [f.text for f in find_figures("+5.1 [+2.1, +8.2] points (296 pairs) at 80.0%, torch 2.13, 3-12 objects")]
    ['+5.1 [+2.1, +8.2]', '296 pairs', '80.0%']
    """
    text = text.replace("\u2212", "-").replace("\u2013", "-")
    figures, taken = [], []
    for m in _INTERVAL.finditer(text):
        numbers = []
        if m.group(1):
            numbers.append(_number(m.group(1), m.group(2)))
        numbers += [_number(m.group(3), ""), _number(m.group(4), "")]
        figures.append((m.start(), Figure(" ".join(m.group().split()), 0, numbers, interval=True)))
        taken.append(m.span())
    for m in _PAIRS.finditer(text):
        if int(m.group(1)) < 20:
            continue  # pairs of objects (the 9 Wedge pairs), not the pairs of a paired run
        figures.append((m.start(), Figure(m.group(), 0, [("", m.group(1), "")], pairs=True)))
    for m in _SINGLE.finditer(text):
        if any(a <= m.start() < b for a, b in taken) or _VERSION_BEFORE.search(text[:m.start()]) \
                or _LEVEL.match(text, m.start()):
            continue
        figures.append((m.start(), Figure(m.group(), 0, [(m.group(1) or "", m.group(2), m.group(3))])))
    figures.sort(key=lambda f: f[0])
    for offset, figure in figures:
        figure.line = text.count("\n", 0, offset)
    return [figure for _, figure in figures]


def _number(token, percent):
    token = token.strip()
    if token == "never":
        return ("", "never", "")
    sign = token[0] if token[0] in "+-" else ""
    return (sign, token.lstrip("+-"), percent)


# --- matching ------------------------------------------------------------------------------------


def _decimals(digits):
    return len(digits.split(".")[1]) if "." in digits else 0


def _parse_output(text):
    """Per line, the list of numbers (sign, digits, exponent, percent) an output holds."""
    lines = []
    for line in text.splitlines():
        numbers = []
        for m in _OUT_NUM.finditer(line):
            if m.group(5):
                numbers.append(("", "never", None, ""))
            else:
                numbers.append((m.group(1), m.group(2).rstrip("."), m.group(3), m.group(4)))
        lines.append(numbers)
    return lines


def _value(number):
    sign, digits, exponent, _ = number
    value = float(f"{digits}e{exponent or 0}")
    return -value if sign == "-" else value


def _same(page, out, *, loose_sign):
    """Whether the page's number (sign, digits, percent) writes the output's number."""
    p_sign, p_digits, p_percent = page
    if p_digits == "never" or out[1] == "never":
        return p_digits == out[1]
    o_sign, o_digits, o_exponent, o_percent = out
    if p_sign == "-" and o_sign != "-":
        return False
    if p_sign == "+" and o_sign == "-":
        return False
    if not p_sign and o_sign == "-" and not loose_sign:
        return False
    k = _decimals(p_digits)
    page_value = float(p_digits)
    out_value = abs(_value(out))
    out_k = _decimals(o_digits) - (int(o_exponent) if o_exponent else 0)
    candidates = [(out_value, out_k)]
    if p_percent and not o_percent:  # a share written as a percent
        candidates.append((out_value * 100, out_k - 2))
    if o_percent and not p_percent:
        candidates.append((out_value / 100, out_k + 2))
    for value, precision in candidates:
        if precision >= k and abs(value - page_value) <= 0.5 * 10 ** -k * (1 + 1e-9) + 1e-12:
            return True
        if precision < k and abs(value - page_value) < 1e-12:
            return True
    return False


def _found(figure, parsed):
    """Whether ``figure`` is in one of the ``parsed`` outputs (line lists of numbers)."""
    numbers = figure.numbers
    for lines in parsed:
        for line in lines:
            if not figure.interval:
                if any(_same(numbers[0], out, loose_sign=True) for out in line):
                    return True
                continue
            n = len(numbers)
            for i in range(len(line) - n + 1):
                if all(_same(numbers[j], line[i + j], loose_sign=False) for j in range(n)):
                    return True
    return False


def _pairs_found(figure, texts):
    count = figure.numbers[0][1]
    pattern = re.compile(rf"(?<![\w.])({count} pairs\b|{count} \({count} pairs\)|{count} of \d+ pairs)")
    return any(pattern.search(text) for text in texts)


def _sd(values):
    m = sum(values) / len(values)
    return (sum((v - m) ** 2 for v in values) / (len(values) - 1)) ** 0.5


#: What a derived figure may call: the mean and the sample standard deviation (n - 1).
_CALLS = {"mean": lambda values: sum(values) / len(values), "sd": _sd}
_OPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv}


def _evaluate(expression):
    def walk(node):
        if isinstance(node, ast.Expression):
            return walk(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return node.value
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            return -walk(node.operand) if isinstance(node.op, ast.USub) else walk(node.operand)
        if isinstance(node, ast.BinOp) and type(node.op) in _OPS:
            return _OPS[type(node.op)](walk(node.left), walk(node.right))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _CALLS \
                and not node.keywords:
            return _CALLS[node.func.id]([walk(arg) for arg in node.args])
        raise ValueError(f"only numbers, + - * / ( ), mean() and sd() in a derived figure, got {expression!r}.")

    return walk(ast.parse(expression, mode="eval"))


def _derived_ok(figure_text, expression, parsed):
    """An error message, or None where the expression's decimals are in the outputs and it rounds to the figure."""
    for m in re.finditer(r"(?<![\w.])(\d+\.\d+)", expression):
        if not _found(Figure(m.group(), 0, [("", m.group(1), "")]), parsed):
            return f"the operand {m.group()} of {figure_text} = {expression} is in none of its outputs"
    value = _evaluate(expression)
    m = re.fullmatch(r"([+\-]?)(\d+(?:\.\d+)?)(%?)", figure_text.replace("\u2212", "-"))
    if not m:
        return f"a derived figure is one number, got {figure_text!r}"
    sign = "-" if value < 0 else ""
    written = (sign, f"{abs(value):.12f}", None, "")
    if not _same((m.group(1), m.group(2), ""), written, loose_sign=False):
        return f"{figure_text} = {expression} gives {value:.6g}"
    return None


def _read_outputs(names, cache, outputs=OUTPUTS):
    parsed, texts, missing = [], [], []
    for name in sorted(names):
        path = os.path.join(outputs, name)
        if not os.path.isfile(path):
            missing.append(name)
            continue
        if name not in cache:
            if name.endswith(".png"):
                cache[name] = ("", [])
            else:
                with open(path, errors="replace") as f:
                    text = f.read()
                cache[name] = (text, _parse_output(text))
        texts.append(cache[name][0])
        parsed.append(cache[name][1])
    return parsed, texts, missing


def check_page(path, *, cache=None, outputs=OUTPUTS):
    """The figures of one page that are not found in the outputs it names for them.

    Parameters
    ----------
    path : str
        The page, relative to the repository root or absolute.
    cache : dict or None, default=None
        Parsed outputs shared between calls.
    outputs : str, default=OUTPUTS
        The folder of the outputs the page names.

    Returns
    -------
    problems : list of str
        ``"PAGE:LINE: FIGURE ..."`` for each figure not found, each derived figure
        that does not hold, each output named that does not exist.
    """
    cache = {} if cache is None else cache
    full = path if os.path.isabs(path) else os.path.join(ROOT, path)
    rel = os.path.relpath(full, ROOT) if full.startswith(ROOT + os.sep) else os.path.basename(full)
    with open(full) as f:
        text = f.read()
    problems = []
    for unit in read_units(text, rst=full.endswith(".rst"), outputs=outputs):
        parsed, texts, missing = _read_outputs(unit.outputs, cache, outputs)
        for name in missing:
            problems.append(f"{rel}:{unit.line}: names the output {name}, which is not in studies/outputs/")
        derived = dict(unit.derived)
        for figure_text, expression in unit.derived:
            if figure_text not in unit.text.replace("\u2212", "-"):
                problems.append(f"{rel}:{unit.line}: the derived figure {figure_text} is not in its paragraph")
            error = _derived_ok(figure_text, expression, parsed)
            if error:
                problems.append(f"{rel}:{unit.line}: {error}")
        for figure in find_figures(unit.text):
            if "*" in unit.given or figure.text in unit.given or figure.text in derived:
                continue
            ok = _pairs_found(figure, texts) if figure.pairs else _found(figure, parsed)
            if not ok:
                where = ", ".join(sorted(unit.outputs)) or "no output named"
                problems.append(f"{rel}:{unit.line + figure.line}: {figure.text} not found ({where})")
    return problems


def pages():
    """The pages :data:`PAGES` names, relative to the repository root."""
    found = []
    for pattern in PAGES:
        found += sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, pattern)))
    return found


def check_pages(paths=None):
    """:func:`check_page` over ``paths`` (default: every page of :data:`PAGES`)."""
    cache, problems = {}, []
    for path in paths or pages():
        problems += check_page(path, cache=cache)
    return problems


# --- headers of the outputs ----------------------------------------------------------------------


_HAS = {
    "command": re.compile(r'^# command: \S|^# provenance \{.*"command": "', re.M),
    "commit": re.compile(r'^# commit: [0-9a-f]{7,40}\b|^# provenance \{.*"commit": "[0-9a-f]{7,40}', re.M),
    "date": re.compile(r"(?<!\d)20\d\d-\d\d-\d\d(?!\d)"),
}
_EXTERNAL = re.compile(r"^# external: \S", re.M)


def missing_header(path):
    """What an output's header, with its sidecar, does not name: a list among "command", "commit", "date".

    An output starts with ``# command: ...`` and ``# commit: HASH, DATE`` (the
    scripts' :func:`harness.provenance.header`), with ``# provenance {...}`` and
    ``# commit: HASH`` (``sklearn-hardness`` stamped by :func:`harness.provenance.stamp`)
    or with the one ``# provenance {...}`` line of older commands (command,
    commit and date in it). What a file cannot hold (a CSV table, an image) or
    its header leaves out is in its sidecar ``NAME.provenance`` (never in the
    output itself). A source the project did not run (a copy of statistics
    supplied to it) says so in its sidecar with ``# external: ...``: it has a
    command and a date, and no commit of ours.
    """
    head = ""
    if not path.endswith(".png"):
        with open(path, errors="replace") as f:
            head = "".join(f.readline() for _ in range(6))
    sidecar = path + ".provenance"
    if os.path.isfile(sidecar):
        with open(sidecar) as f:
            head += f.read()
    lacks = [field for field, pattern in _HAS.items() if not pattern.search(head)]
    if "commit" in lacks and _EXTERNAL.search(head):
        lacks.remove("commit")
    return lacks


def main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("pages", nargs="*", help="pages to check (default: README, studies/ and docs/)")
    args = ap.parse_args(argv)
    problems = check_pages(args.pages or None)
    for problem in problems:
        print(problem)
    print(f"{len(problems)} figure(s) not found in their outputs" if problems else "every figure found")
    return 1 if problems else 0


if __name__ == "__main__":
    raise SystemExit(main())
