# Writes a C++ source defining `const char SYMBOL[]` (declared in HEADER) as
# the text of INPUT that follows its marker line MARKER, byte for byte, in a
# raw string literal. Run at build time by export/CMakeLists.txt, so editing
# INPUT rebuilds the library:
#   cmake -DINPUT=<file> -DOUTPUT=<file.cpp> -DHEADER=<include> -DSYMBOL=<name> -DMARKER=<line> -P embed_text.cmake
foreach(var INPUT OUTPUT HEADER SYMBOL MARKER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "embed_text.cmake: -D${var}=... is required")
  endif()
endforeach()
file(READ "${INPUT}" text)
string(FIND "${text}" "${MARKER}\n" at)
if(at EQUAL -1)
  message(FATAL_ERROR "embed_text.cmake: ${INPUT} has no line '${MARKER}' after which its embedded text begins")
endif()
string(LENGTH "${MARKER}\n" marker_length)
math(EXPR at "${at} + ${marker_length}")
string(SUBSTRING "${text}" ${at} -1 text)
# The raw string's delimiter must not occur in the text it closes.
set(delimiter "furnace_embed")
string(FIND "${text}" ")${delimiter}\"" clash)
if(NOT clash EQUAL -1)
  message(FATAL_ERROR "embed_text.cmake: ${INPUT} contains ')${delimiter}\"', which would end the raw string")
endif()
file(WRITE "${OUTPUT}.tmp"
     "// Generated from ${INPUT} by export/embed_text.cmake: do not edit.\n"
     "#include \"${HEADER}\"\n\n"
     "const char furnace::exporter::${SYMBOL}[] = R\"${delimiter}(${text})${delimiter}\";\n")
file(RENAME "${OUTPUT}.tmp" "${OUTPUT}")
