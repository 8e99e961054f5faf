# CMake generated Testfile for 
# Source directory: /work/wt/io
# Build directory: /work/wt/io/build-asan
# 
# This file includes the relevant testing commands required for 
# testing this directory and lists subdirectories to be tested as well.
subdirs("apps/fulcrum")
subdirs("tests")
