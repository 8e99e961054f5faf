file(REMOVE_RECURSE
  "libfulcrum.a"
)
