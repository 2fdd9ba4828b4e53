# Build step (cmake -P): minifies the mesh script with terser and writes it as a C++ header.
# In: TERSER (the terser program), INPUT (the readable .js), MINIFIED (the .min.js to write),
#     OUTPUT (the header), MAX_BYTES (the size the minified script must not exceed).
# Fails when terser fails, when the result is too large, or when it holds "]]>" (the writer puts
# it in a CDATA section).
foreach(var TERSER INPUT MINIFIED OUTPUT MAX_BYTES)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "embed_script.cmake: ${var} is not set")
  endif()
endforeach()

# Debian's terser is a Node.js program whose modules live in /usr/share/nodejs; a Node.js from
# elsewhere (e.g. NodeSource) does not look there by itself.
set(node_path "/usr/share/nodejs")
if(DEFINED ENV{NODE_PATH} AND NOT "$ENV{NODE_PATH}" STREQUAL "")
  set(node_path "$ENV{NODE_PATH}:${node_path}")
endif()
# The script's own object properties (not DOM or API names) may be renamed too: they are listed
# here, and must not be names of properties the script reads from the browser.
set(own_properties "record|colours|bicubic|tensor|affine|colour|meshShape|gradient|tile|tileImage|key|xy|rgb|indices|mesh|gradmeshRecord|gradmeshMesh|ctx|col|scaleAt|ay")
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env NODE_PATH=${node_path}
          ${TERSER} ${INPUT} --ecma 2020 --compress passes=3 --mangle
          --mangle-props "regex=/^(${own_properties})$/" --output ${MINIFIED}
  RESULT_VARIABLE status
  ERROR_VARIABLE errors)
if(NOT status EQUAL 0)
  message(FATAL_ERROR "terser could not minify ${INPUT}:\n${errors}")
endif()

file(READ ${MINIFIED} script)
string(STRIP "${script}" script)
string(LENGTH "${script}" bytes)
if(bytes GREATER MAX_BYTES)
  message(FATAL_ERROR "the minified mesh script is ${bytes} bytes, over the budget of ${MAX_BYTES}")
endif()
string(FIND "${script}" "]]>" cdataEnd)
if(NOT cdataEnd EQUAL -1)
  message(FATAL_ERROR "the minified mesh script contains \"]]>\", which would end its CDATA section")
endif()
string(FIND "${script}" ")gmjs\"" delimiter)
if(NOT delimiter EQUAL -1)
  message(FATAL_ERROR "the minified mesh script contains the raw-string delimiter )gmjs\"")
endif()

file(WRITE ${OUTPUT}.tmp
  "// Generated from formats/svg/script/mesh_polyfill.js by terser at build time: do not edit.\n"
  "#pragma once\n\n"
  "namespace gm {\n\n"
  "constexpr char kMeshPolyfillScript[] = R\"gmjs(${script})gmjs\";\n\n"
  "}  // namespace gm\n")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)
message(STATUS "mesh script: ${bytes} bytes minified")
