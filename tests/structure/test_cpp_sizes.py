"""The C++ engine's size rules: no source file in engines/sph/src over 400 lines, no function over 80 lines, and no
physics header includes the deck parser's header (deck.h): the deck parser fills plain parameter structs that the
physics code takes.

Function lengths come from a small brace matcher (`cpp_functions`) that blanks comments, string and character
literals and preprocessor lines first, so braces in them do not count. It knows namespaces, classes, brace
initialisers (a constructor's member initialisers included) and function bodies; a lambda or a block inside a
function belongs to that function.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from paths import REPO

SRC = REPO / "engines" / "sph" / "src"
MAX_FILE_LINES = 400
MAX_FUNCTION_LINES = 80
#: The deck parser's own files: only they may include deck.h.
DECK_PARSER = re.compile(r"deck(_\w+)?\.(h|cpp)$")

_SCOPE = re.compile(r"^(?:template\s*<.*>\s*)?(?:inline\s+)?(?:namespace|class|struct|union|enum|extern)\b", re.S)
_ACCESS = re.compile(r"\s*(?:(?:public|private|protected)\s*:(?!:)\s*)*")
_QUALIFIERS = re.compile(r"(?:\)|\b(?:const|noexcept|override|final|mutable|try)|->\s*[\w:<>,\s*&]+)\s*$")


def cpp_sources() -> list[Path]:
    """Every C++ source and header of the engine (src/ and its subfolders)."""
    return sorted(p for p in SRC.rglob("*") if p.suffix in {".h", ".hpp", ".cpp", ".cc"})


def blank_comments_and_literals(text: str) -> str:
    """`text` with comments, string and character literals and preprocessor lines replaced by spaces (newlines
    kept, so line numbers hold). A quote after a number's digits is a digit separator (1'000), not a literal."""
    out, i, n = list(text), 0, len(text)

    def blank(start: int, end: int) -> None:
        for k in range(start, min(end, n)):
            if out[k] != "\n":
                out[k] = " "

    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":  # a preprocessor line, with its continuations
            end = i
            while end < n and (text[end] != "\n" or text[end - 1] == "\\"):
                end += 1
            blank(i, end)
            i = end
            continue
        if c == "\n":
            line_start, i = True, i + 1
            continue
        if not c.isspace():
            line_start = False
        if text.startswith("//", i):
            end = text.find("\n", i)
            end = n if end < 0 else end
            blank(i, end)
            i = end
        elif text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            blank(i, end)
            i = end
        elif c == '"' and i > 0 and text[i - 1] == "R":  # raw string R"delim( ... )delim"
            open_paren = text.find("(", i)
            closing = ")" + text[i + 1:open_paren] + '"'
            end = text.find(closing, open_paren)
            end = n if end < 0 else end + len(closing)
            blank(i, end)
            i = end
        elif c == '"' or (c == "'" and not re.search(r"(?:^|[^\w'])\d[\w']*$", text[max(0, i - 40):i])):
            end = i + 1
            while end < n and text[end] != c:
                end += 2 if text[end] == "\\" else 1
            blank(i, end + 1)
            i = end + 1
        else:
            i += 1
    return "".join(out)


def _function_name(header: str) -> str:
    """The name a function header declares: the word before its parameter list ('<lambda>' for a lambda)."""
    head = re.sub(r"__attribute__\s*\(\(.*?\)\)|\[\[.*?\]\]", " ", header).split("(", 1)[0].rstrip()
    if head.endswith("]"):
        return "<lambda>"
    match = re.search(r"(operator\s*\S+|[\w:~]+)\s*(?:<[^<>]*>)?$", head)
    return match.group(1) if match else "<function>"


def cpp_functions(text: str) -> list[tuple[str, int, int]]:
    """(name, first line, last line) of every function defined in the C++ source `text`; a function runs from
    its header's first line to its closing brace, lines counted from 1."""
    code = blank_comments_and_literals(text)
    functions: list[tuple[str, int, int]] = []
    stack: list[tuple[str, int, str]] = []  # (scope | function | block | init, header start offset, name)
    header_start = 0
    for i, c in enumerate(code):
        if c == ";" and not any(kind in ("function", "init") for kind, _, _ in stack):
            header_start = i + 1
        elif c == "{":
            if any(kind == "function" for kind, _, _ in stack):
                stack.append(("block", i, ""))
                continue
            if any(kind == "init" for kind, _, _ in stack):
                stack.append(("init", i, ""))
                continue
            raw = code[header_start:i]
            start = header_start + _ACCESS.match(raw).end()
            header = " ".join(code[start:i].split())
            if _SCOPE.match(header):
                stack.append(("scope", i, ""))
                header_start = i + 1
            elif "(" in header and (_QUALIFIERS.search(header) or header.endswith("}")):
                stack.append(("function", start, _function_name(header)))
            else:
                stack.append(("init", i, ""))
        elif c == "}" and stack:
            kind, start, name = stack.pop()
            if kind == "function":
                functions.append((name, code.count("\n", 0, start) + 1, code.count("\n", 0, i) + 1))
                header_start = i + 1
            elif kind == "scope":
                header_start = i + 1
    return functions


SNIPPET = r'''// a comment with a brace {
#define OPEN {
namespace sph {
/* a block comment } { */
struct Point {
  double x{0.0}, y = {1.0};
  Point(double a, double b) : x{a}, y(b) {
    const char* s = "}}";  // a string with braces
    const char c = '{';
  }
 public:
  double norm() const { return x * x + y * y; }
};
const int table[] = {1'000, 2};
template <int D>
double twice(double v) {
  auto f = [&](double w) {
    return R"x(raw { text)x" == nullptr ? w : 2 * w;
  };
  if (v > 0) {
    return f(v);
  }
  return 0.0;
}
}  // namespace sph
'''


def test_the_scanner_finds_each_function_and_its_lines():
    assert cpp_functions(SNIPPET) == [("Point", 7, 10), ("norm", 12, 12), ("twice", 15, 24)]


def test_the_scanner_ignores_braces_in_comments_and_literals():
    blanked = blank_comments_and_literals(SNIPPET)
    assert blanked.count("{") == blanked.count("}") == 11
    assert len(blanked) == len(SNIPPET) and blanked.count("\n") == SNIPPET.count("\n")
    assert "1'000" in blanked  # a digit separator is not a character literal


@pytest.mark.parametrize("path", cpp_sources(), ids=lambda p: p.relative_to(SRC).as_posix())
def test_source_files_are_short(path):
    lines = path.read_text().count("\n")
    assert lines <= MAX_FILE_LINES, f"{path.relative_to(REPO)} has {lines} lines (at most {MAX_FILE_LINES})"


@pytest.mark.parametrize("path", cpp_sources(), ids=lambda p: p.relative_to(SRC).as_posix())
def test_functions_are_short(path):
    long = [f"{name} (lines {first}-{last}: {last - first + 1})" for name, first, last in cpp_functions(path.read_text())
            if last - first + 1 > MAX_FUNCTION_LINES]
    assert not long, f"{path.relative_to(REPO)}: functions over {MAX_FUNCTION_LINES} lines: {', '.join(long)}"


def test_only_the_deck_parser_includes_deck_h():
    including = [p.relative_to(SRC).as_posix() for p in cpp_sources()
                 if p.suffix in {".h", ".hpp"} and not DECK_PARSER.search(p.name)
                 and re.search(r'^\s*#\s*include\s*"(?:\.\./)*deck\.h"', p.read_text(), re.M)]
    assert not including, f"physics headers include the deck parser's deck.h: {', '.join(including)}"
