"""Faults in the input: bad keys, values, case files, arguments and lists.

Each function adds its faults in the order of the table (ids are positions); fault_table.py
calls them in that order."""
import os
import random
import resource
import shutil

from faults.checks import leftovers, read_json, short
from faults.harness import BASE_TOML


def issue_approach(F):
    """A load no solve can meet (from the issue)."""
    base, add = F.base, F.add

    def f5(d):
        r = F.run(["run", base, "-o", d, "-q", "--set", "load.approach=1e6"], timeout=min(F.timeout, 20))
        lost = []
        if os.path.exists(os.path.join(d, "summary.json")):
            lost.append("summary.json written for a failed solve")
        lost += leftovers(d)
        return F.verdict(r, {3: "handled"}, ["load.approach"], lost)
    add("--set load.approach=1e6 (mean pressure > 1000 E*)", f5)


def issue_long_list(F):
    """A --set list that is too long (from the issue)."""
    base, add = F.base, F.add

    def f9(d):
        vals = ",".join("%.7g" % (0.01 + i * 1e-6) for i in range(10001))
        return F.expect_refusal(["sweep", base, "-o", d, "-q", "--set", "load.force=" + vals],
                                [("10000", "10 000", "10,000")], new_dir=d, timeout=min(F.timeout, 20))
    add("10 001 values in a --set list (sweep)", f9)


def issue_quiet(F):
    """-q prints nothing; an unknown subcommand (from the issue)."""
    base, add = F.base, F.add

    def f14(d):
        r = F.run(["run", base, "-o", d, "-q"])
        wrong = ["-q printed: " + short(r.out + r.err, 80)] if (r.out.strip() or r.err.strip()) else []
        return F.verdict(r, {0: "handled"}, [], leftovers(d), wrong)
    add("`gfmd run -q` on success prints nothing", f14)

    def f14b(d):
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01"])
        wrong = ["-q printed: " + short(r.out + r.err, 80)] if (r.out.strip() or r.err.strip()) else []
        return F.verdict(r, {0: "handled"}, [], leftovers(d), wrong)
    add("`gfmd sweep -q` on success prints nothing", f14b)

    add("unknown subcommand `gfmd rnu base.toml`",
        lambda d: F.expect_refusal(["rnu", base], ["rnu"]))


def case_inputs(F):
    """Bad keys, values and case files."""
    base, add = F.base, F.add

    add("typo in a --set key (solver.max_iteration)",
        lambda d: F.expect_refusal(["run", base, "-o", d, "--set", "solver.max_iteration=5"],
                                   ["max_iteration"], new_dir=d))

    def typo_file(d):
        p = F.write("typo.toml", BASE_TOML.replace("nx = 64", "nxx = 64"))
        return F.expect_refusal(["run", p, "-o", d], ["nxx"], new_dir=d)
    add("typo in a case-file key ([grid] nxx)", typo_file)

    for what, setting, frag in [
            ("wrong type (grid.nx=\"sixty\")", 'grid.nx="sixty"', "grid.nx"),
            ("float for an integer (grid.nx=64.5)", "grid.nx=64.5", "grid.nx"),
            ("negative size (grid.lx=-4)", "grid.lx=-4", "grid.lx"),
            ("zero grid (grid.nx=0)", "grid.nx=0", "grid.nx"),
            ("NaN (load.force=nan)", "load.force=nan", "load.force"),
            ("inf (elastic.contact_modulus=inf)", "elastic.contact_modulus=inf", "contact_modulus"),
            ("out of range (elastic.poisson=0.6)", "elastic.poisson=0.6", "poisson"),
            ("zero radius (indenter.radius=0)", "indenter.radius=0", "radius"),
            ("unknown section (foo.bar=1)", "foo.bar=1", "foo"),
            ("without '=' (load.force)", "load.force", "load.force"),
            ("with an empty value (load.force=)", "load.force=", "load.force")]:
        add("--set " + what,
            lambda d, s=setting, fr=frag: F.expect_refusal(["run", base, "-o", d, "--set", s], [fr], new_dir=d))

    def huge(d):
        limit = 8 << 30

        def cap():
            resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        r = F.run(["run", base, "-o", d, "--set", "grid.nx=65536"], preexec=cap)
        return F.verdict(r, {2: "refused"}, [("memory", "grid.nx")], leftovers(d),
                         note="(ulimit -v 8 GiB as a safety net)")
    add("grid beyond memory (grid.nx=65536: 32 GiB a field)", huge)

    def dup_set(d):
        r = F.run(["run", base, "-o", d, "-q", "--set", "load.force=0.01", "--set", "load.force=0.02"])
        s = read_json(os.path.join(d, "summary.json")) or {}
        wrong = []
        if r.rc == 0 and abs(float(s.get("normal_force", 0)) - 0.02) > 1e-6:
            wrong.append("normal_force %s: the last --set did not win" % s.get("normal_force"))
        return F.verdict(r, {0: "handled", 2: "refused"}, ["load.force"] if r.rc == 2 else [], leftovers(d), wrong,
                         "last one wins" if r.rc == 0 and not wrong else "")
    add("duplicate --set keys (load.force twice)", dup_set)

    def dup_file(d):
        p = F.write("dupkey.toml", BASE_TOML.replace("nx = 64", "nx = 64\nnx = 32"))
        return F.expect_refusal(["run", p, "-o", d], [("nx", "dupkey.toml")], new_dir=d)
    add("duplicate key in the case file (nx twice)", dup_file)

    def two_loads(d):
        p = F.write("twoloads.toml", BASE_TOML.replace("force = 0.01", "force = 0.01\npressure = 0.001"))
        return F.expect_refusal(["run", p, "-o", d], ["load"], new_dir=d)
    add("two loads in the case file (force and pressure)", two_loads)

    add("comma list given to `run` (load.force=0.01,0.02)",
        lambda d: F.expect_refusal(["run", base, "-o", d, "--set", "load.force=0.01,0.02"], ["sweep"], new_dir=d))

    def empty_case(d):
        p = F.write("empty.toml", "")
        return F.expect_refusal(["run", p, "-o", d], [("empty.toml", "indenter", "load")], new_dir=d)
    add("empty case file", empty_case)

    def garbage(d):
        p = F.path("garbage.toml")
        with open(p, "wb") as f:
            f.write(bytes(random.Random(7).randrange(256) for _ in range(4096)))
        return F.expect_refusal(["run", p, "-o", d], ["garbage.toml"], new_dir=d)
    add("binary garbage as the case file", garbage)

    def big_case(d):
        p = F.write("big.toml", BASE_TOML + ("# padding " + "x" * 100 + "\n") * 11000)
        return F.expect_refusal(["run", p, "-o", d], [("big.toml", "MB")], new_dir=d)
    add("case file of 1.2 MB (comment padding)", big_case)

    def dir_case(d):
        os.makedirs(os.path.join(d, "casedir"))
        return F.expect_refusal(["run", os.path.join(d, "casedir"), "-o", os.path.join(d, "o")], ["casedir"],
                                new_dir=os.path.join(d, "o"))
    add("a directory given as the case", dir_case)

    add("missing case file",
        lambda d: F.expect_refusal(["run", F.path("no_such_case.toml"), "-o", d], ["no_such_case.toml"], new_dir=d))

    def unreadable(d):
        os.makedirs(d)
        p = os.path.join(d, "locked.toml")
        shutil.copy(base, p)
        os.chmod(p, 0)
        out = os.path.join(d, "o")
        r = F.run(["run", p, "-o", out, "-q"])
        os.chmod(p, 0o644)
        if F.is_root:
            return F.verdict(r, {0: "handled"}, [], leftovers(out),
                             note="run as root: chmod 000 does not stop root reading it, so this does not apply")
        return F.verdict(r, {2: "refused"}, ["locked.toml"], leftovers(out))
    add("unreadable case file (chmod 000)", unreadable)

    def fifo(d):
        os.makedirs(d)
        p = os.path.join(d, "pipe.toml")
        os.mkfifo(p)
        return F.expect_refusal(["run", p, "-o", os.path.join(d, "o")], ["pipe.toml"], timeout=20,
                                new_dir=os.path.join(d, "o"))
    add("a FIFO as the case file (must not hang)", fifo)

    add("/dev/zero as the case file (must not hang)",
        lambda d: F.expect_refusal(["run", "/dev/zero", "-o", d], ["/dev/zero"], timeout=20, new_dir=d))


def bad_arguments(F):
    """Unknown option, no case."""
    base, add = F.base, F.add

    add("unknown option (--fast)", lambda d: F.expect_refusal(["run", base, "-o", d, "--fast"], ["--fast"], new_dir=d))
    add("no case argument (`gfmd run -o DIR`)",
        lambda d: F.expect_refusal(["run", "-o", d], ["case"], new_dir=d))


def checkpoint_sweep_args(F):
    """--checkpoint-interval and sweep lists."""
    base, add = F.base, F.add

    def ckpt(d, value, expect):
        r = F.run(["run", base, "-o", d, "-q", "--checkpoint-interval", value])
        return F.verdict(r, expect, ["checkpoint-interval"] if r.rc == 2 else [], leftovers(d))
    add("--checkpoint-interval 0", lambda d: ckpt(d, "0", {0: "handled", 2: "refused"}))
    add("--checkpoint-interval -5", lambda d: ckpt(d, "-5", {2: "refused"}))
    add("--checkpoint-interval nan", lambda d: ckpt(d, "nan", {2: "refused"}))

    def sweep_string(d):
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "indenter.type=hertz,eggcrate"])
        return F.verdict(r, {0: "handled", 2: "refused"}, ["indenter.type"] if r.rc == 2 else [], leftovers(d))
    add("sweep over a non-numeric key (indenter.type=hertz,eggcrate)", sweep_string)

    def sweep_two_lists(d):
        r = F.run(["sweep", base, "-o", d, "-q", "--set", "load.force=0.005,0.01", "--set", "elastic.poisson=0.2,0.3"])
        return F.verdict(r, {2: "refused"}, [("load.force", "elastic.poisson", "one key")], leftovers(d))
    add("sweep with lists on two keys", sweep_two_lists)

    add("sweep with an empty list item (load.force=0.01,,0.02)",
        lambda d: F.expect_refusal(["sweep", base, "-o", d, "--set", "load.force=0.01,,0.02"], ["load.force"],
                                   new_dir=d))


def flow_plot_args(F):
    """Flow / plot / green on the wrong directories or ranges."""
    add = F.add

    def flow_foreign(d):
        os.makedirs(d)
        F.write(os.path.join(d, "notes.txt"), "mine\n")
        return F.expect_refusal(["flow", d], [os.path.basename(d)], watch=[d])
    add("`gfmd flow` on a directory that is not a run", flow_foreign)

    def flow_bad_direction(d):
        F.base_run(d)
        return F.expect_refusal(["flow", d, "--direction", "diagonal"], ["direction"], watch=[d])
    add("`gfmd flow --direction diagonal` on a run", flow_bad_direction)

    def plot_empty(d):
        os.makedirs(d)
        return F.expect_refusal(["plot", d], [os.path.basename(d)], watch=[d])
    add("`gfmd plot` on an empty directory", plot_empty)
    add("`gfmd plot` on a missing directory",
        lambda d: F.expect_refusal(["plot", d], [os.path.basename(d)], new_dir=d))

    add("`gfmd green --from 10 --to 1`",
        lambda d: F.expect_refusal(["green", "--poisson", "0.25", "--from", "10", "--to", "1", "-o",
                                    os.path.join(F.tmp, "phi.csv")], [("--from", "--to", "from")]))


def encoding(F):
    """A Windows-written case file."""
    add = F.add

    def bom_crlf(d):
        p = F.path("windows.toml")
        with open(p, "wb") as f:
            f.write(b"\xef\xbb\xbf" + BASE_TOML.replace("\n", "\r\n").encode())
        r = F.run(["run", p, "-o", d, "-q"])
        return F.verdict(r, {0: "handled", 2: "refused"}, ["windows.toml"] if r.rc == 2 else [], leftovers(d))
    add("case file with a UTF-8 BOM and CRLF line ends", bom_crlf)
