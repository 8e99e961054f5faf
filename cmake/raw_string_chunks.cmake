# Helpers for the cmake -P scripts that embed text files into C++ sources
# (cmake/embed_text.cmake, viewer/embed_assets.cmake).

# Sets VAR to the text of FILE as raw string literals of at most 16,000
# characters, one per line, each followed by a comma (ISO C++ only promises
# 65,536 characters per literal, and -Wpedantic checks it); an empty file
# gives one empty literal. DELIMITER is the raw strings' delimiter, which the
# file must not contain.
function(fulcrum_raw_string_chunks var file delimiter)
  file(READ "${file}" content)
  string(FIND "${content}" ")${delimiter}\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${file} contains the raw-string delimiter )${delimiter}\"")
  endif()
  string(LENGTH "${content}" length)
  set(out "")
  set(pos 0)
  while(pos LESS length)
    string(SUBSTRING "${content}" ${pos} 16000 chunk)
    string(APPEND out "    R\"${delimiter}(${chunk})${delimiter}\",\n")
    math(EXPR pos "${pos} + 16000")
  endwhile()
  if(length EQUAL 0)
    set(out "    \"\",\n")
  endif()
  set(${var} "${out}" PARENT_SCOPE)
endfunction()

# Writes SOURCE to OUT only when it differs, so that an unchanged input does
# not recompile its generated source.
function(fulcrum_write_if_changed out source)
  if(EXISTS "${out}")
    file(READ "${out}" previous)
    if(previous STREQUAL source)
      return()
    endif()
  endif()
  file(WRITE "${out}" "${source}")
endfunction()
