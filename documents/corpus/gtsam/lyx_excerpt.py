"""How math.tex and LieGroups.tex were cut from GTSAM's LyX documents: the
LyX container markup dropped, every LaTeX character of the formulas and
macros kept.

    python3 lyx_excerpt.py math GTSAM/doc | cat -s > math.tex.body
    python3 lyx_excerpt.py LieGroups GTSAM/doc | cat -s > LieGroups.tex.body
    python3 lyx_excerpt.py ImuFactor GTSAM/doc | cat -s > ImuFactor.tex.body

(the excerpt is the body after the header comment of the .tex file; `cat -s`
squeezes the runs of blank lines the dropped markup leaves).

Rules (LyX 2.3 format 544):
- a `FormulaMacro` inset is its `\\newcommand` line, verbatim (LyX's copy
  of the expansion after it is dropped);
- a `Formula` inset is its LaTeX, verbatim (`$…$`, `\\[…\\]`,
  `\\begin{equation}…\\end{equation}`, `\\begin{align*}…`, `\\begin{eqnarray*}…`);
- a `Section`/`Subsection`/`Subsubsection` layout (starred or not) is
  `\\section{…}`/`\\subsection{…}`/`\\subsubsection{…}` (`\\subsubsection*{…}`),
  a paragraph its words, one line of the LyX file per line;
- a label inset is `\\label{…}`, a reference `\\ref{…}`, a citation
  `\\cite{…}`, a quote inset `"`, a footnote `\\footnote{…}`;
- font changes (`\\series`, `\\emph`, `\\family`, …) and page breaks are dropped.

math.tex is the macros of doc/math.lyx's preamble (lines 117 to 420), then
the sections "3D Rotations" (lines 4438 to 4705, without its "Retractions")
and "3D Rigid Transformations" (lines 4810 to 5606, up to its
"Retractions").

LieGroups.tex is doc/macros.lyx (which doc/LieGroups.lyx includes) whole,
then the "Actions" subsections of doc/LieGroups.lyx's sections "2D
Rotations" (lines 1390 to 1505), "2D Rigid Transformations" (lines 1775 to
1871), "3D Rotations" (lines 2479 to 2538), "3D Rigid Transformations"
(lines 2797 to 2957), and the section "3D Similarity Transformations" (lines
2958 to 3169).

ImuFactor.tex is doc/macros.lyx whole, then doc/ImuFactor.lyx's own macros
(lines 103 to 146) and its sections from "Local Coordinates" to "Noise
Propagation in Combined IMU Factor" (lines 620 to 2091).
"""

import os
import re
import sys

RECIPES = {
    "math": [("math.lyx", [(117, 420), (4438, 4705), (4810, 5606)])],
    "LieGroups": [
        ("macros.lyx", [(1, None)]),
        (
            "LieGroups.lyx",
            [(1390, 1505), (1775, 1871), (2479, 2538), (2797, 2957), (2958, 3169)],
        ),
    ],
    "ImuFactor": [("macros.lyx", [(1, None)]), ("ImuFactor.lyx", [(103, 146), (620, 2091)])],
}
DROPPED = re.compile(
    r"^\\(series|emph|family|shape|size|bar|strikeout|xout|uuline|uwave|noun|color|lang)\b"
)


def convert(lines):
    out = []
    stack = []  # open insets and layouts
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("\\begin_layout "):
            kind = line.split()[1]
            stack.append(("layout", kind))
            if kind.rstrip("*") in ("Section", "Subsection", "Subsubsection"):
                out.append("\\" + kind.lower() + "{")
        elif line == "\\end_layout":
            kind = stack.pop()[1] if stack else ""
            if kind.rstrip("*") in ("Section", "Subsection", "Subsubsection"):
                out[-1] = out[-1].rstrip() + "}"
            out.append("")
        elif line.startswith("\\begin_inset "):
            kind = line.split()[1]
            rest = line[len("\\begin_inset " + kind) :].strip()
            if kind in ("Formula", "FormulaMacro"):
                body = [rest] if rest else []
                i += 1
                while lines[i] != "\\end_inset":
                    body.append(lines[i])
                    i += 1
                if kind == "FormulaMacro":
                    # The definition; LyX keeps its expansion on the next line.
                    body = body[:1]
                out.append("\n".join(body))
            elif kind == "CommandInset":
                fields = {}
                i += 1
                while lines[i] != "\\end_inset":
                    key, _, value = lines[i].partition(" ")
                    fields[key] = value.strip('"')
                    i += 1
                command = fields.get("LatexCommand", "")
                target = fields.get("name") or fields.get("reference") or fields.get("key", "")
                if command in ("label", "ref", "eqref", "vpageref", "cite"):
                    out.append("\\" + command + "{" + target + "}")
            elif kind == "Quotes":
                out.append('"')
                stack.append(("inset", kind))
            elif kind == "Foot":
                out.append("\\footnote{")
                stack.append(("inset", kind))
            else:
                stack.append(("inset", kind))
        elif line == "\\end_inset":
            kind = stack.pop()[1] if stack else ""
            if kind == "Foot":
                out.append("}")
        elif line.startswith("\\") and (DROPPED.match(line) or line.startswith("\\begin_inset")):
            pass
        elif line.startswith("status "):
            pass
        elif line.startswith("\\") and not line.startswith("\\\\"):
            # Other LyX markup (page breaks, `\\noindent`).
            pass
        else:
            out.append(line)
        i += 1
    return "\n".join(out)


def main(recipe, directory):
    for name, ranges in RECIPES[recipe]:
        with open(os.path.join(directory, name), encoding="utf-8") as f:
            lines = f.read().split("\n")
        for start, end in ranges:
            end = end or len(lines)
            print(f"% [doc/{name}, lines {start}-{end}]")
            print(convert(lines[start - 1 : end]))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
