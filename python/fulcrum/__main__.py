"""``python3 -m fulcrum COMMAND``: commands of the Python package (docs/python.md).

    python3 -m fulcrum sweep SCENE.json --set "bodies[ball].restitution=0:1:11" --steps 300 --out results.csv
"""
import sys

COMMANDS = {"sweep": "a parameter grid over a scene, locally or on a Dask scheduler (docs/scale-out.md)"}


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if not argv or argv[0] in ("-h", "--help"):
        print("usage: python3 -m fulcrum COMMAND ...\n\ncommands:")
        for name, what in COMMANDS.items():
            print(f"  {name:8} {what}")
        return 0 if argv else 2
    if argv[0] == "sweep":
        from .sweep import main as sweep

        return sweep(argv[1:])
    print(f"python3 -m fulcrum: unknown command '{argv[0]}' (commands: {', '.join(COMMANDS)})", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())
