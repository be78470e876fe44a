"""Faults made through the Python package.

Each function adds its faults in the order of the table (ids are positions); fault_table.py
calls them in that order."""
import os
import sys

from faults.checks import added, changed, short, snapshot


def python_package(F):
    """The Python package (only with --python-pkg)."""
    base, add = F.base, F.add

    if F.pkg:
        def py(d, code, frags, watch=(), home=None, timeout=None):
            os.makedirs(d, exist_ok=True)
            # exit 2: the exception expected was raised (printed as EXC type message); 0: none was
            prog = ("import sys, warnings\nsys.path.insert(0, %r)\ntry:\n    import gfmd\n"
                    "    assert hasattr(gfmd, 'run'), 'no gfmd.run in ' + str(gfmd.__path__)\n"
                    "except (ImportError, AssertionError) as e:\n    print('IMPORT', e, file=sys.stderr)\n    sys.exit(7)\n"
                    "try:\n%s\nexcept Exception as e:\n    print('EXC', type(e).__name__, e, file=sys.stderr)\n"
                    "    sys.exit(2)\nsys.exit(0)\n" % (F.pkg, "\n".join("    " + l for l in code.splitlines())))
            before = {w: snapshot(w) for w in watch}
            r = F.run([[sys.executable, "-c", prog]], cwd=d, env=dict(F.env, HOME=home) if home else None,
                      timeout=timeout)
            if r.rc == 7 and r.err.startswith("IMPORT"):
                return "not tried", "-", "cannot import gfmd from %s: %s" % (F.pkg, short(r.err[7:], 80))
            lost = []
            for w in watch:
                after = snapshot(w)
                lost += changed(before[w], after) + ["wrote " + x for x in added(before[w], after)]
            return F.verdict(r, {2: "refused"}, frags, lost)

        def py_foreign(d):
            out = os.path.join(d, "mine")
            os.makedirs(out)
            F.write(os.path.join(out, "spectrum.csv"), "mine\n")
            return py(d, "gfmd.run(%r, output=%r)" % (base, out), ["mine"], watch=[out])
        add("Python gfmd.run(output=foreign dir with spectrum.csv)", py_foreign)
        def py_home(d):
            home = os.path.join(d, "emptyhome")
            os.makedirs(home)
            return py(d, "gfmd.run(%r, output=%r)" % (base, home), ["home directory"], watch=[home], home=home)
        add("Python gfmd.run(output=$HOME), HOME an empty dir", py_home)
        add("Python gfmd.run(set=['solver.max_iteration=3'])",
            lambda d: py(d, "gfmd.run(%r, set=['solver.max_iteration=3'], output=%r)" % (base, os.path.join(d, "o")),
                         ["max_iteration"]))
        add("Python gfmd.sweep with 10 001 values",
            lambda d: py(d, "gfmd.sweep(%r, 'load.force', [0.01 + i * 1e-6 for i in range(10001)], %r)"
                         % (base, os.path.join(d, "o")), [("10000", "10 000", "10,000")], timeout=min(F.timeout, 20)))

        def py_save(d):
            out = os.path.join(d, "mine")
            os.makedirs(out)
            F.write(os.path.join(out, "notes.txt"), "mine\n")
            code = ("t = gfmd.Topography.hertz(64, 4.0, radius=1.0)\n"
                    "r = gfmd.solve(t, force=0.01)\nr.save(%r)" % out)
            return py(d, code, ["mine"], watch=[out])
        add("Python Result.save(foreign dir)", py_save)

        add("Python gfmd.solve(pressure=nan)",
            lambda d: py(d, "t = gfmd.Topography.hertz(64, 4.0, radius=1.0)\ngfmd.solve(t, pressure=float('nan'))",
                         ["pressure"]))
