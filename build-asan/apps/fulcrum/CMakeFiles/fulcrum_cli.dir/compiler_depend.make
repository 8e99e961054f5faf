# Empty compiler generated dependencies file for fulcrum_cli.
# This may be replaced when dependencies are built.
