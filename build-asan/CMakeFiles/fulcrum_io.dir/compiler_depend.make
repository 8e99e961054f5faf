# Empty compiler generated dependencies file for fulcrum_io.
# This may be replaced when dependencies are built.
