file(REMOVE_RECURSE
  "libfulcrum_io.a"
)
