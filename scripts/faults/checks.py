"""File checks used by the fault table: snapshots of directories, what changed, what a run left
behind, message fragments, and small file makers (height maps, .npy, cases)."""
import hashlib
import json
import os
import stat
import struct


def snapshot(path):
    """{relative path: (kind, sha1 or '', mtime_ns)} of everything under path (hidden too)."""
    snap = {}
    if not os.path.lexists(path):
        return snap
    if not os.path.isdir(path):
        return {".": ("file", _sha1(path), os.stat(path).st_mtime_ns)}
    for dirpath, dirnames, filenames in os.walk(path):
        for d in dirnames:
            full = os.path.join(dirpath, d)
            snap[os.path.relpath(full, path)] = ("dir", "", 0)
        for f in filenames:
            full = os.path.join(dirpath, f)
            try:
                st = os.lstat(full)
                digest = _sha1(full) if stat.S_ISREG(st.st_mode) else ""
                snap[os.path.relpath(full, path)] = ("file", digest, st.st_mtime_ns)
            except OSError:
                pass
    return snap


def _sha1(path):
    h = hashlib.sha1()
    try:
        with open(path, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
    except OSError as e:
        return "unreadable:%s" % e
    return h.hexdigest()


def _top(rel):
    return rel.split(os.sep, 1)[0]


def changed(before, after, ignore=()):
    """Files of `before` deleted or changed in `after`; names (or first path parts) in ignore
    are not compared."""
    out = []
    for rel, (kind, digest, _) in sorted(before.items()):
        if _top(rel) in ignore or os.path.basename(rel) in ignore:
            continue
        if rel not in after:
            out.append("deleted " + rel)
        elif kind == "file" and after[rel][1] != digest:
            out.append("changed " + rel)
    return out


def added(before, after, ignore=()):
    return sorted(rel for rel in after if rel not in before and _top(rel) not in ignore
                  and os.path.basename(rel) not in ignore)


def leftovers(path, staging_ok=False):
    """Temporary files (*.tmp*, .maps.tmp.nc) and, unless staging_ok, .gfmd-staging left under path."""
    bad = []
    if not os.path.isdir(path):
        return bad
    for dirpath, dirnames, filenames in os.walk(path):
        rel_dir = os.path.relpath(dirpath, path)
        for d in list(dirnames):
            if d == ".gfmd-staging":
                if not staging_ok:
                    bad.append(os.path.normpath(os.path.join(rel_dir, d)) + "/")
                dirnames.remove(d)
        for f in filenames:
            if ".tmp" in f:
                bad.append(os.path.normpath(os.path.join(rel_dir, f)))
    return bad


def has_fragment(text, frag):
    low = text.lower()
    if isinstance(frag, (tuple, list)):
        return any(f.lower() in low for f in frag)
    return frag.lower() in low


def frag_text(frag):
    return " or ".join(repr(f) for f in frag) if isinstance(frag, (tuple, list)) else repr(frag)


def short(text, n=140):
    lines = [l.strip() for l in text.strip().splitlines() if l.strip()]
    s = " / ".join(lines)
    return (s[: n - 1] + "…") if len(s) > n else s


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def pngs_newer(d, t_ns):
    for dirpath, _, files in os.walk(d):
        for f in files:
            if f.endswith(".png") or ".png" in f:
                try:
                    if os.stat(os.path.join(dirpath, f)).st_mtime_ns > t_ns:
                        return True
                except OSError:
                    pass
    return False


def npy_bytes(descr, shape, raw, fortran=False):
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (descr, fortran, tuple(shape))
    pad = 64 - (10 + len(header) + 1) % 64
    header = header + " " * pad + "\n"
    return b"\x93NUMPY\x01\x00" + struct.pack("<H", len(header)) + header.encode("latin1") + raw


def file_case(name, path, extra_indenter="", grid="lx = 10.0\nunit = \"um\"", load="pressure = 0.01"):
    return ("[grid]\n%s\n\n[indenter]\ntype = \"file\"\npath = \"%s\"\n%s\n\n[load]\n%s\n\n"
            "[output]\npng = false\n" % (grid, path, extra_indenter, load))
