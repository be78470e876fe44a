"""A master-curve file of the standard linear solid E(omega) = 10 - 9/(1 + i omega) (E0 = 1,
E_inf = 10, tau = 1), for the tests of elastic.viscoelastic = "master_curve"."""


def write_sls_master_curve(path, rows_per_decade=20, first_decade=-4, decades=8):
    """Writes rows omega, E', E'' at rows_per_decade per decade from 10^first_decade over
    `decades` decades (both ends included); returns the path."""
    rows = ["omega,storage,loss"]
    for k in range(rows_per_decade * decades + 1):
        w = 10.0 ** (first_decade + k / rows_per_decade)
        e = 10 - 9 / (1 + 1j * w)
        rows.append(f"{w!r},{e.real!r},{e.imag!r}")
    path.write_text("\n".join(rows) + "\n")
    return path
