"""Atomic writers shared by the study scripts: figures as PNG + PDF, tables as CSV."""
import csv
import os

import matplotlib.pyplot as plt


def save(fig, base):
    """Writes base.png and base.pdf (each to a temporary name, then renamed) and closes fig."""
    for ext in ("png", "pdf"):
        tmp = f"{base}.tmp.{ext}"
        fig.savefig(tmp)
        os.replace(tmp, f"{base}.{ext}")
    plt.close(fig)


def save_png(fig, path):
    """Writes path as PNG (to a temporary name, then renamed; the temporary file is removed
    if drawing fails) and closes fig."""
    tmp = f"{path}.tmp.{os.getpid()}"
    try:
        fig.savefig(tmp, format="png")
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.remove(tmp)


def write_csv(path, head, rows):
    with open(path + ".tmp", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(head)
        w.writerows(rows)
    os.replace(path + ".tmp", path)
