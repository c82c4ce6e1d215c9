"""Read and write Fortran namelist files: the subset ffrf's case files and input/study.nml use.

A file is a sequence of groups `&name key = value, key = v1, v2 /`; `!` starts a comment to the
end of the line (outside quotes); values are quoted strings ('...' or "...", a doubled quote
inside is one quote), numbers (1, 2.5, 1.0e-4, 1.0d-4), logicals (.true., .false., T, F) or
comma/space-separated lists of them; keys are case-insensitive (stored lower case). Repeated
groups (&body, &family) keep their order. No solver logic: only text.

    groups = namelist.parse(open("input/engine_rc1.nml").read())
    crank = namelist.find(groups, "body", name="crank")
    crank.set("mesh_file", "/tmp/crank_lc4.msh")
    text = namelist.format_groups(groups)
"""
import re

__all__ = ["NamelistError", "Group", "parse", "read", "find", "find_all", "format_value",
           "format_groups"]


class NamelistError(Exception):
    """A file that is not a namelist of the supported subset (the message says where)."""


class Group:
    """One namelist group: its name and its (key, values) items in order. `values` is always a
    list (one entry for a scalar)."""

    def __init__(self, name, items=None):
        self.name = name.lower()
        self.items = list(items or [])

    def keys(self):
        return [key for key, _ in self.items]

    def get(self, key, default=None):
        """The value of `key`: a scalar when it has one value, else the list; default if
        absent."""
        key = key.lower()
        for k, values in self.items:
            if k == key:
                return values[0] if len(values) == 1 else list(values)
        return default

    def get_list(self, key, default=None):
        """The values of `key` as a list (default if absent)."""
        key = key.lower()
        for k, values in self.items:
            if k == key:
                return list(values)
        return default

    def set(self, key, value):
        """Set `key` (a scalar or a list), replacing its value or appending it."""
        key = key.lower()
        values = list(value) if isinstance(value, (list, tuple)) else [value]
        for i, (k, _) in enumerate(self.items):
            if k == key:
                self.items[i] = (k, values)
                return
        self.items.append((key, values))

    def remove(self, key):
        key = key.lower()
        self.items = [(k, v) for k, v in self.items if k != key]

    def __repr__(self):
        return f"Group({self.name!r}, {self.items!r})"


_TOKEN = re.compile(r"""
    (?P<string>'(?:[^']|'')*'|"(?:[^"]|"")*")
  | (?P<group>&[A-Za-z_][A-Za-z0-9_]*)
  | (?P<end>/)
  | (?P<equals>=)
  | (?P<comma>,)
  | (?P<word>[^\s,=/'"!&]+)
""", re.VERBOSE)


def _strip_comments(text):
    """Text with every `!` comment removed (quotes respected)."""
    out = []
    for line in text.splitlines():
        quote = None
        cut = len(line)
        for i, ch in enumerate(line):
            if quote:
                if ch == quote:
                    quote = None
            elif ch in "'\"":
                quote = ch
            elif ch == "!":
                cut = i
                break
        out.append(line[:cut])
    return "\n".join(out)


def _value(token, kind):
    if kind == "string":
        quote = token[0]
        return token[1:-1].replace(quote * 2, quote)
    low = token.lower()
    if low in (".true.", "t", ".t."):
        return True
    if low in (".false.", "f", ".f."):
        return False
    try:
        return int(token)
    except ValueError:
        pass
    try:
        return float(low.replace("d", "e"))
    except ValueError as exc:
        raise NamelistError(f"value {token!r} is neither a quoted string, a number nor a "
                            f"logical") from exc


def parse(text, source="namelist"):
    """The groups of a namelist text, in order. Raises NamelistError naming the group and
    key for text outside a group, a key without '=', or an unterminated group."""
    tokens = []
    body = _strip_comments(text)
    pos = 0
    while pos < len(body):
        if body[pos].isspace():
            pos += 1
            continue
        match = _TOKEN.match(body, pos)
        if not match:
            line = body.count("\n", 0, pos) + 1
            raise NamelistError(f"{source}, line {line}: cannot read {body[pos:pos + 20]!r}")
        tokens.append((match.lastgroup, match.group(0)))
        pos = match.end()

    groups = []
    i = 0
    while i < len(tokens):
        kind, token = tokens[i]
        if kind != "group":
            raise NamelistError(f"{source}: {token!r} outside a group (a group starts with "
                                f"&name and ends with /)")
        group = Group(token[1:])
        i += 1
        key = None
        while True:
            if i >= len(tokens):
                raise NamelistError(f"{source}: group &{group.name} has no closing /")
            kind, token = tokens[i]
            if kind == "end":
                i += 1
                break
            if kind == "word" and i + 1 < len(tokens) and tokens[i + 1][0] == "equals":
                key = token.lower()
                group.items.append((key, []))
                i += 2
                continue
            if kind == "comma":
                i += 1
                continue
            if kind in ("word", "string"):
                if key is None:
                    raise NamelistError(f"{source}, &{group.name}: value {token!r} before any "
                                        f"'key ='")
                group.items[-1][1].append(_value(token, kind))
                i += 1
                continue
            raise NamelistError(f"{source}, &{group.name}: unexpected {token!r}")
        for key, values in group.items:
            if not values:
                raise NamelistError(f"{source}, &{group.name}: key {key} has no value")
        groups.append(group)
    return groups


def read(path):
    """parse() of a file."""
    with open(path) as stream:
        return parse(stream.read(), source=str(path))


def find_all(groups, group_name, **match):
    """The groups called `group_name` whose keys equal the given values (strings compared
    case-sensitively, as ffrf does)."""
    group_name = group_name.lower()
    return [g for g in groups if g.name == group_name
            and all(g.get(k) == v for k, v in match.items())]


def find(groups, group_name, **match):
    """The one group called `group_name` that matches; NamelistError if none or several."""
    found = find_all(groups, group_name, **match)
    if len(found) != 1:
        what = ", ".join(f"{k} = {v!r}" for k, v in match.items())
        raise NamelistError(f"{len(found)} groups &{group_name}"
                            + (f" with {what}" if what else "") + ", expected exactly one")
    return found[0]


def format_value(value):
    """Namelist text of one value: repr-exact floats, quoted strings, .true./.false."""
    if isinstance(value, bool):
        return ".true." if value else ".false."
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    text = str(value)
    return "'" + text.replace("'", "''") + "'"


def format_groups(groups):
    """Namelist text of the groups, one group per line."""
    lines = []
    for group in groups:
        items = ", ".join(f"{key} = " + ", ".join(format_value(v) for v in values)
                          for key, values in group.items)
        lines.append(f"&{group.name} {items} /" if items else f"&{group.name} /")
    return "\n".join(lines) + "\n"
