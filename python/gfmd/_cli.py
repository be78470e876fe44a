"""The console script `gfmd`: the same program as the CMake build's, installed inside the package."""
import os
import sys


def main() -> None:
    exe = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bin", "gfmd")
    if not os.access(exe, os.X_OK):
        sys.stderr.write(f"gfmd: the program is missing from the package ({exe}); reinstall with pip install .\n")
        sys.exit(1)
    os.execv(exe, [exe] + sys.argv[1:])  # argument vector, no shell


if __name__ == "__main__":
    main()
