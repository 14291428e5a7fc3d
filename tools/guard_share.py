"""Guard lines as a share of executable lines, per folder of a package (default ``idkit/``).

Run from the repository root: ``python tools/guard_share.py [package folder] [--files]``.

The counting rule (docs/development.md, "Argument contracts"):

- **Executable lines** hold at least one code token; blank lines, comment-only lines and the
  lines of docstrings (the first string of a module, class or function) are not executable.
- **Guard lines** are the executable lines inside
  (a) an ``if`` (or ``elif``) branch whose body only raises: the test and the body, when every
  statement of the body is an assignment, an expression or a ``raise`` and the last one is a
  ``raise``;
  (b) an ``assert``;
  (c) a ``try`` whose body is one or two simple statements and whose every handler ends in a
  ``raise`` (a coercion written by hand);
  (d) a ``for`` loop whose body is made only of such ``if`` branches.
- **Declaration lines** are the lines of ``@accepts(...)`` decorators: the declared contracts,
  counted apart from the hand-written guards.

The rule is syntactic: a check interleaved with computation is not counted, so the share is a
lower bound of the code spent on checking.
"""

from __future__ import annotations

import ast
import io
import sys
import tokenize
from collections import defaultdict
from pathlib import Path

_SIMPLE = (ast.Assign, ast.AnnAssign, ast.AugAssign, ast.Expr, ast.Raise, ast.Pass)


def _lines(node: ast.AST) -> set[int]:
    return set(range(node.lineno, node.end_lineno + 1))


def _raising_body(body: list[ast.stmt]) -> bool:
    return bool(body) and isinstance(body[-1], ast.Raise) and all(isinstance(s, _SIMPLE) for s in body)


def _if_guard_lines(node: ast.If) -> set[int]:
    """Lines of each branch of an if/elif chain that only raises (the test and its body)."""
    lines: set[int] = set()
    if _raising_body(node.body):
        lines |= set(range(node.lineno, node.body[-1].end_lineno + 1))
    return lines


def _guard_lines(tree: ast.AST) -> set[int]:
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If):
            lines |= _if_guard_lines(node)
        elif isinstance(node, ast.Assert):
            lines |= _lines(node)
        elif isinstance(node, ast.Try):
            if (len(node.body) <= 2 and all(isinstance(s, _SIMPLE) for s in node.body) and node.handlers
                    and all(_raising_body(h.body) for h in node.handlers) and not node.orelse
                    and not node.finalbody):
                lines |= _lines(node)
        elif isinstance(node, ast.For):
            if node.body and all(isinstance(s, ast.If) and _raising_body(s.body) and not s.orelse
                                 for s in node.body):
                lines |= _lines(node)
    return lines


def _declaration_lines(tree: ast.AST) -> set[int]:
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            for decorator in node.decorator_list:
                call = decorator.func if isinstance(decorator, ast.Call) else decorator
                if getattr(call, "id", getattr(call, "attr", None)) == "accepts":
                    lines |= _lines(decorator)
    return lines


def _docstring_lines(tree: ast.AST) -> set[int]:
    lines: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) \
                    and isinstance(first.value.value, str):
                lines |= _lines(first)
    return lines


def _code_lines(source: str) -> set[int]:
    skip = {tokenize.COMMENT, tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT,
            tokenize.ENDMARKER, tokenize.ENCODING}
    lines: set[int] = set()
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type not in skip:
            lines |= set(range(token.start[0], token.end[0] + 1))
    return lines


def count(path: Path) -> dict[str, int]:
    """Total, executable, guard and declaration lines of one module."""
    source = path.read_text()
    tree = ast.parse(source)
    executable = _code_lines(source) - _docstring_lines(tree)
    return {"lines": len(source.splitlines()), "executable": len(executable),
            "guards": len(_guard_lines(tree) & executable),
            "declarations": len(_declaration_lines(tree) & executable)}


def main(argv: list[str]) -> None:
    root = Path(next((a for a in argv if not a.startswith("--")), "idkit"))
    folders: dict[str, dict[str, int]] = defaultdict(lambda: defaultdict(int))
    rows = []
    for path in sorted(root.rglob("*.py")):
        figures = count(path)
        relative = path.relative_to(root)
        folder = relative.parts[0] if len(relative.parts) > 1 else "(root)"
        for key, value in figures.items():
            folders[folder][key] += value
            folders["TOTAL"][key] += value
        rows.append((str(relative), figures))
    header = f"{'':28s} {'lines':>7s} {'exec':>7s} {'guards':>7s} {'share':>6s} {'decl':>5s}"
    print(header)
    listing = rows if "--files" in argv else sorted(folders.items())
    for name, figures in listing:
        if name == "TOTAL":
            continue
        share = figures["guards"] / max(figures["executable"], 1)
        print(f"{name:28s} {figures['lines']:7d} {figures['executable']:7d} {figures['guards']:7d} "
              f"{share:6.1%} {figures['declarations']:5d}")
    total = folders["TOTAL"]
    print(f"{'TOTAL':28s} {total['lines']:7d} {total['executable']:7d} {total['guards']:7d} "
          f"{total['guards'] / total['executable']:6.1%} {total['declarations']:5d}")


if __name__ == "__main__":
    main(sys.argv[1:])
