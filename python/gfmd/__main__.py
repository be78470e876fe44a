"""python -m gfmd ARGS: the gfmd program."""
from ._cli import main

main()
