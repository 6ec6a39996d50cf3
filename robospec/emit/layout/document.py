"""A document of text, line breaks and groups, printed to fit a line width.

This is the layout model of ruff's formatter (the ``ruff_formatter`` crate): a group prints on
one line when its content, and what follows it up to the next line break, fits; otherwise its
soft line breaks become new lines. The extras ruff builds Python's layout from are here too,
with ruff's semantics, because the generated modules must come out exactly as ``ruff format``
would write them: conditional content and indentation keyed on another group's mode,
conditional groups, ``fits_expanded`` (measure content as if broken, allowing long text) and
``best_fit_parenthesize`` (wrap an expression in parentheses only when that makes it fit).

Widths count characters: the emitter writes only characters one column wide (see
:mod:`robospec.emit.layout.literals`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

FLAT, EXPANDED = "flat", "expanded"
# how far a measurement looks: up to the first line break, or every line (optionally letting
# text run past the width: only what comes before and after the text then matters)
FIRST_LINE, ALL_LINES, ALL_LINES_OVERFLOW = "first", "all", "overflow"
SOFT, SOFT_OR_SPACE, HARD, EMPTY = "soft", "soft_or_space", "hard", "empty"
INDENT_WIDTH = 4


@dataclass(slots=True)
class Text:
    text: str  # one line, every character one column wide


@dataclass(slots=True)
class Line:
    mode: str  # SOFT: nothing when flat; SOFT_OR_SPACE: a space; HARD/EMPTY: always breaks


@dataclass(slots=True)
class Concat:
    items: list[Doc]


@dataclass(slots=True)
class Group:
    content: Doc
    id: int | None = None
    expand: bool = False  # set for a group that must break (or holds one that must)


@dataclass(slots=True)
class Indent:
    content: Doc


@dataclass(slots=True)
class IfGroup:
    """Content printed only while a group (the enclosing one, or ``group_id``) is in ``mode``."""

    content: Doc
    mode: str
    group_id: int | None = None


@dataclass(slots=True)
class IndentIfGroupBreaks:
    content: Doc
    group_id: int


@dataclass(slots=True)
class ConditionalGroup:
    """A group, but only while ``group_id``'s group is in ``mode``; else plain content."""

    content: Doc
    mode: str
    group_id: int
    expand: bool = False


@dataclass(slots=True)
class FitsExpanded:
    """Measured as broken (text may overflow) while ``condition`` (mode, group) holds."""

    content: Doc
    condition: tuple[str, int | None] | None = None
    propagate: bool = False


@dataclass(slots=True)
class BestFitParenthesize:
    """The content flat; else in parentheses on its own indented line, if that fits."""

    content: Doc
    id: int | None = None


Doc = (
    Text
    | Line
    | Concat
    | Group
    | Indent
    | IfGroup
    | IndentIfGroupBreaks
    | ConditionalGroup
    | FitsExpanded
    | BestFitParenthesize
)

SPACE = Text(" ")
SOFT_LINE = Line(SOFT)
SOFT_LINE_OR_SPACE = Line(SOFT_OR_SPACE)
HARD_LINE = Line(HARD)
EMPTY_LINE = Line(EMPTY)


def concat(*items: Doc) -> Concat:
    return Concat(list(items))


def soft_block_indent(content: Doc) -> Doc:
    """The content on its own indented lines when the enclosing group breaks."""
    return concat(Indent(concat(SOFT_LINE, content)), SOFT_LINE)


def if_group_breaks(content: Doc, group_id: int | None = None) -> IfGroup:
    return IfGroup(content, EXPANDED, group_id)


def if_group_fits_on_line(content: Doc, group_id: int | None = None) -> IfGroup:
    return IfGroup(content, FLAT, group_id)


@dataclass(frozen=True, slots=True)
class _Args:
    indent: int
    mode: str
    measure: str = FIRST_LINE

    def with_mode(self, mode: str) -> _Args:
        return _Args(self.indent, mode, self.measure)

    def indented(self) -> _Args:
        return _Args(self.indent + 1, self.mode, self.measure)


@dataclass
class _Measure:
    line_width: int
    pending_indent: int


def print_document(document: Doc, width: int) -> str:
    propagate_expand(document)
    return _Printer(width).print(document)


def propagate_expand(node: Doc) -> bool:
    """Mark every group holding a hard line break (or a group that must break) as breaking,
    as ruff's ``Document::propagate_expand`` does; true when ``node`` makes its parent break.
    A ``best_fit_parenthesize`` and a ``fits_expanded`` stop the propagation."""
    if isinstance(node, Line):
        return node.mode in (HARD, EMPTY)
    if isinstance(node, Concat):
        expands = False
        for item in node.items:
            expands = propagate_expand(item) or expands
        return expands
    if isinstance(node, (Group, ConditionalGroup)):
        if propagate_expand(node.content):
            node.expand = True
        return node.expand
    if isinstance(node, FitsExpanded):
        if propagate_expand(node.content):
            node.propagate = True
        return False
    if isinstance(node, BestFitParenthesize):
        propagate_expand(node.content)
        return False
    if isinstance(node, (Indent, IfGroup, IndentIfGroupBreaks)):
        return propagate_expand(node.content)
    return False


@dataclass
class _Printer:
    width: int
    out: list[str] = field(default_factory=list)
    line_width: int = 0
    line_has_text: bool = False
    pending_indent: int = 0
    # a parent group was measured to fit on this line: nested groups need no measuring
    measured_group_fits: bool = False
    group_modes: dict[int, str] = field(default_factory=dict)
    stack: list[tuple[Doc, _Args]] = field(default_factory=list)

    def print(self, document: Doc) -> str:
        self.stack = [(document, _Args(0, EXPANDED))]
        while self.stack:
            node, args = self.stack.pop()
            self._print(node, args)
        return "".join(self.out)

    def _push(self, node: Doc, args: _Args) -> None:
        if isinstance(node, Concat):
            self.stack.extend((item, args) for item in reversed(node.items))
        else:
            self.stack.append((node, args))

    def _print(self, node: Doc, args: _Args) -> None:
        if isinstance(node, Text):
            self._text(node.text)
        elif isinstance(node, Line):
            if args.mode == FLAT and node.mode in (SOFT, SOFT_OR_SPACE):
                if node.mode == SOFT_OR_SPACE:
                    self._text(" ")
            else:
                if self.line_has_text:
                    self._newline()
                if node.mode == EMPTY:
                    self._newline()
                self.pending_indent = args.indent
        elif isinstance(node, Concat):
            self._push(node, args)
        elif isinstance(node, Group):
            mode = EXPANDED if node.expand else self._flat_group_mode(node.content, node.id, args)
            if node.id is not None:
                self.group_modes[node.id] = mode
            self._push(node.content, args.with_mode(mode))
        elif isinstance(node, BestFitParenthesize):
            self._print_best_fit_parenthesize(node, args)
        elif isinstance(node, IfGroup):
            mode = args.mode if node.group_id is None else self.group_modes[node.group_id]
            if mode == node.mode:
                self._push(node.content, args)
        elif isinstance(node, IndentIfGroupBreaks):
            expanded = self.group_modes[node.group_id] == EXPANDED
            self._push(node.content, args.indented() if expanded else args)
        elif isinstance(node, ConditionalGroup):
            if self.group_modes[node.group_id] == node.mode:
                mode = EXPANDED if node.expand else self._flat_group_mode(node.content, None, args)
                self._push(node.content, args.with_mode(mode))
            else:
                self._push(node.content, args)
        elif isinstance(node, FitsExpanded):
            if self._condition_met(node.condition, args):
                # measured as broken so far: the groups inside must measure themselves
                self.measured_group_fits = False
            self._push(node.content, args)
        elif isinstance(node, Indent):
            self._push(node.content, args.indented())
        else:  # pragma: no cover
            raise TypeError(f"not a document node: {node!r}")

    def _condition_met(self, condition: tuple[str, int | None] | None, args: _Args) -> bool:
        if condition is None:
            return True
        mode, group_id = condition
        return mode == (args.mode if group_id is None else self.group_modes[group_id])

    def _print_best_fit_parenthesize(self, node: BestFitParenthesize, args: _Args) -> None:
        mode = self._flat_group_mode(node.content, node.id, args)
        if mode == EXPANDED:
            # parentheses only if the content then fits; else stay flat and overflow
            if node.id is not None:
                self.group_modes[node.id] = EXPANDED
            probe = _parenthesized_on_own_lines(node.content)
            measure = _Args(args.indent, args.mode, ALL_LINES)
            mode = EXPANDED if self._fits([(probe, measure)]) else FLAT
        if node.id is not None:
            self.group_modes[node.id] = mode
        if mode == EXPANDED:
            self._push(_parenthesized_on_own_lines(node.content), args.with_mode(EXPANDED))
        else:
            self._push(node.content, args.with_mode(FLAT))

    def _flat_group_mode(self, content: Doc, group_id: int | None, args: _Args) -> str:
        if args.mode == FLAT and self.measured_group_fits:
            return FLAT
        self.measured_group_fits = True
        if group_id is not None:
            self.group_modes[group_id] = FLAT
        return FLAT if self._fits([(content, args.with_mode(FLAT))]) else EXPANDED

    def _text(self, text: str) -> None:
        if self.pending_indent:
            self.out.append(" " * (INDENT_WIDTH * self.pending_indent))
            self.line_width += INDENT_WIDTH * self.pending_indent
            self.pending_indent = 0
        self.out.append(text)
        self.line_width += len(text)
        self.line_has_text = True

    def _newline(self) -> None:
        self.out.append("\n")
        self.line_width = 0
        self.line_has_text = False
        self.measured_group_fits = False

    # -- measuring ------------------------------------------------------------------------

    def _fits(self, first: list[tuple[Doc, _Args]]) -> bool:
        """Whether ``first``, then everything still to print, fits up to the first line break
        (or on every line, as each element's measure mode says)."""
        state = _Measure(self.line_width, self.pending_indent)
        local = list(reversed(first))
        rest = len(self.stack) - 1
        while True:
            if local:
                node, args = local.pop()
            elif rest >= 0:
                node, args = self.stack[rest]
                rest -= 1
            else:
                return True
            verdict = self._fits_element(node, args, state, local)
            if verdict is not None:
                return verdict

    def _fits_element(
        self, node: Doc, args: _Args, state: _Measure, local: list[tuple[Doc, _Args]]
    ) -> bool | None:
        if isinstance(node, Text):
            return self._fits_text(node.text, args, state)
        if isinstance(node, Line):
            if args.mode == FLAT:
                if node.mode == SOFT_OR_SPACE:
                    return self._fits_text(" ", args, state)
                return True if node.mode in (HARD, EMPTY) else None
            if args.measure == FIRST_LINE:
                return True
            state.line_width = 0
            state.pending_indent = args.indent
            return None
        if isinstance(node, Concat):
            local.extend((item, args) for item in reversed(node.items))
        elif isinstance(node, Group):
            mode = EXPANDED if node.expand else args.mode
            if node.id is not None:
                self.group_modes[node.id] = mode
            local.append((node.content, args.with_mode(mode)))
        elif isinstance(node, BestFitParenthesize):
            # measured without its parentheses, like a group in the enclosing mode
            if node.id is not None:
                self.group_modes[node.id] = args.mode
            local.append((node.content, args))
        elif isinstance(node, ConditionalGroup):
            if self.group_modes[node.group_id] == node.mode:
                mode = EXPANDED if node.expand else args.mode
                local.append((node.content, args.with_mode(mode)))
            else:
                local.append((node.content, args))
        elif isinstance(node, IfGroup):
            mode = args.mode if node.group_id is None else self.group_modes[node.group_id]
            if mode == node.mode:
                local.append((node.content, args))
        elif isinstance(node, IndentIfGroupBreaks):
            expanded = self.group_modes[node.group_id] == EXPANDED
            local.append((node.content, args.indented() if expanded else args))
        elif isinstance(node, FitsExpanded):
            if args.mode == FLAT and self._condition_met(node.condition, args):
                local.append((node.content, _Args(args.indent, EXPANDED, ALL_LINES_OVERFLOW)))
            elif args.mode == FLAT and node.propagate:
                return False
            else:
                local.append((node.content, args))
        elif isinstance(node, Indent):
            local.append((node.content, args.indented()))
        return None

    def _fits_text(self, text: str, args: _Args, state: _Measure) -> bool | None:
        state.line_width += INDENT_WIDTH * state.pending_indent + len(text)
        state.pending_indent = 0
        if state.line_width > self.width and args.measure != ALL_LINES_OVERFLOW:
            return False
        return None


def _parenthesized_on_own_lines(content: Doc) -> Doc:
    return concat(Text("("), Indent(concat(HARD_LINE, content)), HARD_LINE, Text(")"))
