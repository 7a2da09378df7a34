# Fails when a file includes a library it may not use (cmake -P, run by the build before any
# renderer library compiles; docs/architecture.md explains the layers).
#
# The rule per folder: which renderer/ folders its files may include, and whether they may see
# OpenGL/EGL headers. A folder may always include itself. A header that pulled GL into the CLI
# or into a loader would compile today and break the layering silently; this makes it an error.
#   cmake -DSOURCE_DIR=<repo> -DSTAMP=<file> -P CheckLayering.cmake

cmake_minimum_required(VERSION 3.25)

set(allowed_core "")
set(allowed_scene core)
set(allowed_view core scene)
set(allowed_output core scene view)
set(allowed_verify core scene view output)
set(allowed_render core scene view output)
set(allowed_gl core)
set(allowed_passes core scene view output render gl)
set(allowed_cli core scene view output verify render)
set(allowed_python core scene view output verify render)
set(gl_allowed gl passes)

set(violations "")
foreach(folder core scene view output verify render gl passes cli python)
  if(folder STREQUAL "cli")
    set(dir "${SOURCE_DIR}/cli")
  elseif(folder STREQUAL "python")
    set(dir "${SOURCE_DIR}/python/src")
  else()
    set(dir "${SOURCE_DIR}/renderer/${folder}")
  endif()
  file(GLOB files "${dir}/*.h" "${dir}/*.cpp")
  foreach(file IN LISTS files)
    file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include")
    file(RELATIVE_PATH shown "${SOURCE_DIR}" "${file}")
    foreach(line IN LISTS includes)
      if(line MATCHES "[<\"]renderer/([a-z_]+)/")
        set(target "${CMAKE_MATCH_1}")
        if(NOT target STREQUAL folder AND NOT target IN_LIST allowed_${folder})
          string(APPEND violations "  ${shown}: ${line}\n    (${folder}/ may use: ${allowed_${folder}})\n")
        endif()
      elseif(line MATCHES "<(GL|EGL|KHR|epoxy)/" AND NOT folder IN_LIST gl_allowed)
        string(APPEND violations "  ${shown}: ${line}\n    (only gl/ and passes/ may see OpenGL)\n")
      endif()
    endforeach()
  endforeach()
endforeach()

if(violations)
  message(FATAL_ERROR "layering broken (cmake/CheckLayering.cmake):\n${violations}")
endif()
file(WRITE "${STAMP}" "ok\n")
