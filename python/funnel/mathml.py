"""Mathematics in the HTML report as MathML, which browsers display natively (no scripts, no
network).

Text may hold ``$...$`` segments in a small TeX subset, the one matplotlib's mathtext and the
figure captions use: letters, numbers, operators, ``_`` and ``^`` with a token or a ``{group}``,
``\\sqrt{..}``, ``\\frac{..}{..}``, ``\\mathrm{..}``, ``\\text{..}``, Greek letters (``\\mu``,
``\\beta``, ...), ``\\partial``, ``\\le``, ``\\times`` and the like. Outside ``$...$`` a few
plain-text spellings that the command line writes (``β0``, ``x0/L``, ``x_c/L``, ``√(H/g)``)
are shown as mathematics too; everything else is escaped text.
"""

from __future__ import annotations

import html
import re

GREEK = {
    "alpha": "α", "beta": "β", "gamma": "γ", "delta": "δ", "epsilon": "ε", "varepsilon": "ε", "zeta": "ζ",
    "eta": "η", "theta": "θ", "iota": "ι", "kappa": "κ", "lambda": "λ", "mu": "μ", "nu": "ν", "xi": "ξ",
    "pi": "π", "rho": "ρ", "sigma": "σ", "tau": "τ", "phi": "φ", "varphi": "φ", "chi": "χ", "psi": "ψ",
    "omega": "ω", "Gamma": "Γ", "Delta": "Δ", "Theta": "Θ", "Lambda": "Λ", "Xi": "Ξ", "Pi": "Π",
    "Sigma": "Σ", "Phi": "Φ", "Psi": "Ψ", "Omega": "Ω",
}
OPERATORS = {
    "le": "≤", "leq": "≤", "ge": "≥", "geq": "≥", "ne": "≠", "neq": "≠", "approx": "≈", "sim": "∼",
    "times": "×", "cdot": "⋅", "pm": "±", "to": "→", "rightarrow": "→", "infty": "∞", "ldots": "…",
    "dots": "…", "circ": "∘", "partial": "∂", "lvert": "|", "rvert": "|", "langle": "⟨", "rangle": "⟩",
    "in": "∈", "sum": "∑", "propto": "∝", "degree": "°",
}
SPACES = {",": "0.167em", ":": "0.222em", ";": "0.278em", " ": "0.25em", "quad": "1em", "qquad": "2em"}

#: Plain-text spellings (in command-line output) shown as mathematics: text -> TeX.
PLAIN = (
    ("x_c/L", "x_c/L"), ("x0/L", "x_0/L"), ("x_0/L", "x_0/L"), ("√(H/g)", r"\sqrt{H/g}"),
    ("√(gH)", r"\sqrt{gH}"), ("β0", r"\beta_0"), ("y_b", "y_b"), ("x_c", "x_c"),
)
_PLAIN_RE = re.compile("|".join(re.escape(p) for p, _ in PLAIN) + r"|(?<![\w.])x0(?!\w|\.\d)")
_PLAIN_TEX = dict(PLAIN, x0="x_0")


def _e(text):
    return html.escape(text, quote=False)


class _Parser:
    """Recursive descent over one $...$ segment; each method returns MathML text."""

    def __init__(self, tex):
        self.s, self.i = tex, 0

    def peek(self):
        return self.s[self.i] if self.i < len(self.s) else ""

    def row(self, stop=""):
        items = []
        while self.i < len(self.s) and self.peek() != stop:
            atom = self.atom()
            if atom is None:
                continue
            items.append(self.scripts(atom))
        if stop and self.peek() == stop:
            self.i += 1
        return items[0] if len(items) == 1 else f"<mrow>{''.join(items)}</mrow>"

    def group(self):
        """A {group} or a single atom (the argument of _, ^, \\sqrt, \\frac)."""
        while self.peek() == " ":
            self.i += 1
        if self.peek() == "{":
            self.i += 1
            return self.row("}")
        atom = self.atom()
        return atom if atom is not None else "<mrow></mrow>"

    def raw_group(self):
        """The text of a {group}, unparsed (for \\mathrm and \\text)."""
        if self.peek() != "{":
            return self.group()
        depth, start = 0, self.i
        while self.i < len(self.s):
            c = self.s[self.i]
            depth += c == "{"
            depth -= c == "}"
            self.i += 1
            if depth == 0:
                break
        return self.s[start + 1:self.i - 1]

    def scripts(self, base):
        sub = sup = None
        while self.peek() in ("_", "^"):
            c = self.s[self.i]
            self.i += 1
            if c == "_":
                sub = self.group()
            else:
                sup = self.group()
        if sub is not None and sup is not None:
            return f"<msubsup>{base}{sub}{sup}</msubsup>"
        if sub is not None:
            return f"<msub>{base}{sub}</msub>"
        if sup is not None:
            return f"<msup>{base}{sup}</msup>"
        return base

    def atom(self):
        c = self.peek()
        if c == " ":
            self.i += 1
            return None
        if c == "{":
            self.i += 1
            return self.row("}")
        if c == "\\":
            return self.command()
        if c.isdigit() or (c == "." and self.s[self.i + 1:self.i + 2].isdigit()):
            m = re.match(r"\d*\.?\d+", self.s[self.i:])
            self.i += m.end()
            return f"<mn>{m.group()}</mn>"
        self.i += 1
        if c.isalpha():
            upright = c in "ΓΔΘΛΞΠΣΦΨΩ"
            return f'<mi mathvariant="normal">{_e(c)}</mi>' if upright else f"<mi>{_e(c)}</mi>"
        if c == "-":
            c = "\u2212"
        if c in "()[]|":
            return f'<mo stretchy="false">{_e(c)}</mo>'
        return f"<mo>{_e(c)}</mo>"

    def command(self):
        self.i += 1
        m = re.match(r"[A-Za-z]+|.", self.s[self.i:])
        name = m.group() if m else ""
        self.i += len(name)
        if name in SPACES:
            return f'<mspace width="{SPACES[name]}"></mspace>'
        if name == "sqrt":
            return f"<msqrt>{self.group()}</msqrt>"
        if name in ("frac", "dfrac", "tfrac"):
            num = self.group()
            return f"<mfrac>{num}{self.group()}</mfrac>"
        if name in ("mathrm", "rm", "operatorname"):
            return f'<mi mathvariant="normal">{_e(self.raw_group())}</mi>'
        if name == "text":
            return f"<mtext>{_e(self.raw_group())}</mtext>"
        if name in ("left", "right", "big", "Big"):
            return None
        if name in GREEK:
            variant = ' mathvariant="normal"' if name[0].isupper() else ""
            return f"<mi{variant}>{GREEK[name]}</mi>"
        if name in OPERATORS:
            return f"<mo>{OPERATORS[name]}</mo>"
        if name in ("{", "}", "%", "$", "#", "&", "_"):
            return f"<mo>{_e(name)}</mo>"
        return f"<mtext>{_e(chr(92) + name)}</mtext>"


def tex_to_mathml(tex, display=False):
    """MathML of a TeX-subset formula (without the dollars)."""
    body = _Parser(tex).row()
    mode = ' display="block"' if display else ""
    return f'<math{mode}><semantics>{body}<annotation encoding="application/x-tex">{_e(tex)}</annotation>' \
           "</semantics></math>"


def _plain(text):
    """Escaped text with the PLAIN spellings turned into MathML."""
    out, last = [], 0
    for m in _PLAIN_RE.finditer(text):
        out.append(_e(text[last:m.start()]))
        out.append(tex_to_mathml(_PLAIN_TEX[m.group()]))
        last = m.end()
    out.append(_e(text[last:]))
    return "".join(out)


def text_to_html(text):
    """HTML of a text with $...$ formulas (as MathML); an unpaired $ stays a dollar sign."""
    parts = re.split(r"(?<!\\)\$", str(text))
    if len(parts) % 2 == 0:  # unpaired: keep the last dollar as text
        parts[-2:] = [parts[-2] + "$" + parts[-1]]
    return "".join(_plain(p) if k % 2 == 0 else tex_to_mathml(p) for k, p in enumerate(parts))


#: Symbols of the model parameters (the report's parameter tables).
PARAMETER_TEX = {"theta": r"\theta", "e": "e", "mu": r"\mu", "beta0": r"\beta_0", "radius": "a", "gap": "d",
                 "inertia": r"\kappa", "t_max": r"t_\mathrm{max}", "max_collisions": r"N_\mathrm{coll}"}


def parameter_html(name):
    """HTML of a parameter's name: its symbol as MathML when it has one, else the name."""
    return tex_to_mathml(PARAMETER_TEX[name]) if name in PARAMETER_TEX else _e(name)
