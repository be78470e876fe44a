"""The study file (studies/*.toml), checked before anything runs: load_study returns it as a
dict or raises BadInput naming the key that is wrong (study.py: exit status 2, one line
`gfmd study: FILE: reason`). Also where a study writes its series (series_dir)."""
import math
import os
import tomllib


class BadInput(Exception):
    """A bad study file, setting or option: exit 2 with `gfmd study: <what>: <reason>`."""


# Top-level tables of a case file (src/case/config.cpp: kSections).
CASE_SECTIONS = ("grid", "elastic", "indenter", "load", "friction", "interaction", "solver", "output",
                 "sweep", "stress", "flow")
KINDS = ("sweep", "runs", "percolation", "green", "pull_off")
FIGURES = ("maps", "cross_section", "profiles")
# The columns a pull_off study's rows hold besides its x (scripts/study.py fills them from each
# unloading path's curve.json and the summary of its most tensile point).
PULL_OFF_COLUMNS = ("pull_off_force", "pull_off_approach", "jump_off_approach", "pull_off_contact_radius",
                    "pull_off_extent_longitudinal", "pull_off_extent_transverse", "pull_off_tangential_force")


def _type_name(v):
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "an array",
            dict: "a table"}.get(type(v), type(v).__name__)


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _string(d, key, where, required=False):
    if key not in d:
        if required:
            raise BadInput(f"{where}{key}: missing (a string is needed)")
        return
    if not isinstance(d[key], str):
        raise BadInput(f"{where}{key}: must be a string (got {_type_name(d[key])})")


def _number(d, key, where):
    if key in d and not _is_number(d[key]):
        raise BadInput(f"{where}{key}: must be a number (got {_type_name(d[key])})")


def _settings(d, key, where):
    if key not in d:
        return
    v = d[key]
    if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
        raise BadInput(f"{where}{key}: must be a list of strings (\"key=value\")")
    for x in v:
        if "=" not in x:
            raise BadInput(f"{where}{key}: \"{x}\" is not key=value")


def _tables(d, key, where, required=False):
    if key not in d:
        if required:
            raise BadInput(f"{where}no [[{key}]] table")
        return []
    v = d[key]
    if not isinstance(v, list) or not all(isinstance(x, dict) for x in v):
        raise BadInput(f"{where}{key}: must be an array of tables ([[{key}]]), got {_type_name(v)}")
    if required and not v:
        raise BadInput(f"{where}no [[{key}]] table")
    return v


MAX_SEEDS = 64  # seeds per series (each is a whole sweep)


def parse_seeds(v, where):
    """A series' `seeds`: "A..B" (both included) or a list of integers >= 0; the seeds as a list."""
    if isinstance(v, str):
        a, sep, b = v.partition("..")
        try:
            first, last = int(a), int(b)
        except ValueError:
            first = last = -1
        if not sep or first < 0 or last < first:
            raise BadInput(f'{where}seeds: "{v}" is not FIRST..LAST with 0 <= FIRST <= LAST (e.g. "0..7")')
        seeds = list(range(first, last + 1))
    elif isinstance(v, list) and v and all(isinstance(x, int) and not isinstance(x, bool) and x >= 0 for x in v):
        seeds = list(v)
        if len(set(seeds)) != len(seeds):
            raise BadInput(f"{where}seeds: a seed is listed twice")
    else:
        raise BadInput(f'{where}seeds: must be "FIRST..LAST" (e.g. "0..7") or a list of integers >= 0 '
                       f"(got {_type_name(v)})")
    if len(seeds) > MAX_SEEDS:
        raise BadInput(f"{where}seeds: {len(seeds)} seeds; at most {MAX_SEEDS} per series")
    return seeds


def load_study(path, case_root):
    """The study file as a dict, or BadInput naming the file and the key that is wrong."""
    if not os.path.exists(path):
        raise BadInput("no such file")
    if os.path.isdir(path):
        raise BadInput("is a directory, not a study file (studies/*.toml)")
    try:
        with open(path, "rb") as f:
            study = tomllib.load(f)
    except OSError as e:
        raise BadInput(f"cannot read: {e.strerror}") from None
    except UnicodeDecodeError:
        raise BadInput("not a TOML file (not UTF-8 text)") from None
    except tomllib.TOMLDecodeError as e:
        raise BadInput(f"not valid TOML: {e}") from None
    if "series" not in study:
        found = [k for k in CASE_SECTIONS if isinstance(study.get(k), dict)]
        if found:
            raise BadInput(f"this is a case file ([{found[0]}]), use gfmd run; a study has [[series]] tables "
                           "naming case files (studies/*.toml)")
    series = _tables(study, "series", "", required=True)
    _string(study, "title", "")
    _string(study, "kind", "")
    kind = study.get("kind", "sweep")
    if kind not in KINDS:
        raise BadInput(f"kind: must be one of {', '.join(repr(k) for k in KINDS)} (got {kind!r})")
    for mode in ("quick", "full"):
        if mode in study:
            if not isinstance(study[mode], dict):
                raise BadInput(f"{mode}: must be a table ([{mode}]), got {_type_name(study[mode])}")
            _settings(study[mode], "set", f"{mode}.")
            if "seeds" in study[mode]:
                study[mode]["seeds"] = parse_seeds(study[mode]["seeds"], f"{mode}.")
    if kind == "sweep":
        _string(study, "x", "", required=True)
        _string(study, "y", "", required=True)
        _axes(study)
        cols = study.get("table_columns", [])
        if not isinstance(cols, list) or not all(isinstance(c, str) for c in cols):
            raise BadInput("table_columns: must be a list of strings")
        if "published" in study:
            pub = study["published"]
            if not isinstance(pub, dict):
                raise BadInput(f"published: must be a table ([published]), got {_type_name(pub)}")
            _string(pub, "divide_by", "published.", required=True)
            for key in ("xlabel", "ylabel", "title", "caption"):
                _string(pub, key, "published.")
        _second(study)
    elif kind == "pull_off":
        # One unloading path (gfmd curve) per value of x; its pull-off and the contact there.
        _string(study, "x", "", required=True)
        vals = study.get("values")
        if not isinstance(vals, list) or not vals or not all(_is_number(v) for v in vals):
            raise BadInput("values: must be a non-empty list of numbers (the values of x, one path each)")
        _string(study, "approaches", "", required=True)
        parts = study["approaches"].split(":")
        try:
            ok = (len(parts) == 3 and int(parts[2]) >= 2 and all(math.isfinite(float(v)) for v in parts[:2])
                  and float(parts[0]) > float(parts[1]))
        except ValueError:
            ok = False
        if not ok:
            raise BadInput(f"approaches: must be FROM:TO:N, an unloading path (FROM > TO, finite; N >= 2 "
                           f"points), got {study['approaches']!r}")
        study.setdefault("y", "pull_off_force")
        _string(study, "y", "")
        _axes(study)
        _second(study)
        known = (study["x"],) + PULL_OFF_COLUMNS
        for key, name in (("y", study["y"]), ("second.y", study.get("second", {}).get("y"))):
            if name is not None and name not in known:
                raise BadInput(f"{key}: {name!r} is not a column of a pull_off study (one of {', '.join(known)})")
        for key in ("published", "table_columns", "reference"):
            if key in study:
                raise BadInput(f"{key}: belongs to a sweep study, not to kind = \"pull_off\"")
    elif kind == "runs":
        _string(study, "figure", "")
        figure = study.get("figure", "maps")
        if figure not in FIGURES:
            raise BadInput(f"figure: must be one of {', '.join(repr(k) for k in FIGURES)} (got {figure!r})")
        _number(study, "crop", "")
        if figure in ("maps", "profiles"):
            for i, spec in enumerate(_tables(study, figure, "", required=True), 1):
                _string(spec, "var", f"{figure}[{i}].", required=True)
                _string(spec, "label", f"{figure}[{i}].")
                _string(spec, "cmap", f"{figure}[{i}].")
                _string(spec, "scale_to", f"{figure}[{i}].")
                for key in ("scale", "vmin", "vmax"):
                    _number(spec, key, f"{figure}[{i}].")
    for i, r in enumerate(_tables(study, "reference", ""), 1):
        where = f"reference[{i}]."
        if kind != "sweep":
            raise BadInput(f"{where[:-1]}: reference curves belong to a sweep study")
        for key in ("label", "file", "x", "y"):
            _string(r, key, where, required=True)
        for key in ("color", "style", "panel"):
            _string(r, key, where)
        if r.get("panel", "published") not in ("published", "plain"):
            raise BadInput(f"{where}panel: must be \"published\" or \"plain\" (got {r['panel']!r})")
        _settings(r, "where", where)
        path = os.path.join(case_root, r["file"])
        if not os.path.isfile(path):
            raise BadInput(f"{where}file: {r['file']}: no such file (paths are relative to {case_root})")
        r["_path"] = path
        with open(path, newline="") as f:
            header = [c.strip() for c in f.readline().strip().split(",")]
        for key in [r["x"], r["y"]] + [c.split("=", 1)[0] for c in r.get("where", [])]:
            if key not in header:
                raise BadInput(f"{where}: {r['file']} has no column {key!r} (columns: {', '.join(header)})")
    for i, s in enumerate(series, 1):
        where = f"series[{i}]."
        _string(s, "label", where, required=True)
        for key in ("color", "style"):
            _string(s, key, where)
        _number(s, "x_scale", where)
        _number(s, "y_scale", where)
        if "seeds" in s:
            if kind != "sweep":
                raise BadInput(f"{where}seeds: only a sweep series runs over seeds (kind = \"sweep\")")
            s["seeds"] = parse_seeds(s["seeds"], where)
        for key in ("set", "quick_set", "full_set"):
            _settings(s, key, where)
        if kind == "green":
            p = s.get("poisson")
            if not isinstance(p, list) or not p or not all(_is_number(v) for v in p):
                raise BadInput(f"{where}poisson: must be a non-empty list of numbers")
            continue
        _string(s, "case", where, required=True)
        case = os.path.join(case_root, s["case"])
        if not os.path.isfile(case):
            raise BadInput(f"{where}case: {s['case']}: no such file (case paths are relative to {case_root})")
    return study


def _axes(study):
    """The axis keys a sweep or pull_off study may give."""
    for key in ("xlabel", "ylabel", "xscale", "yscale"):
        _string(study, key, "")
    for key in ("x_scale", "y_scale"):
        _number(study, key, "")


def _second(study):
    """A [second] panel: its quantity y (required) and labels."""
    if "second" in study:
        sec = study["second"]
        if not isinstance(sec, dict):
            raise BadInput(f"second: must be a table ([second]), got {_type_name(sec)}")
        _string(sec, "y", "second.", required=True)
        for key in ("ylabel", "title"):
            _string(sec, key, "second.")


def series_dir(out, i):
    return os.path.join(out, f"series_{i:02d}")


def seed_dir(out, i, seed):
    """Where seed `seed` of series i (a series with `seeds`) writes its sweep."""
    return os.path.join(series_dir(out, i), f"seed_{seed}")
