# Empty dependencies file for fulcrum.
# This may be replaced when dependencies are built.
