# Parts of the library and the one-way order between them.
#
# gfmd_part(NAME [DEPENDS part...] [PUBLIC libs...] [PRIVATE libs...]) makes the static
# library gfmd_NAME from src/NAME/*.cpp, records the parts it may use (DEPENDS and, through
# them, everything below) and links them publicly. gfmd_check_layers() then
#  - at configure time, fails if a file of a part includes a header of a part it may not use
#    ("gfmd/<part>/..." or <gfmd/<part>/...> includes, indented too, in the .hpp, .cpp, .cu
#    and .cuh files of include/gfmd/NAME and src/NAME);
#  - at build time, links each part whole (every object, --whole-archive) with only its
#    declared dependencies into a small program, so that a call into a part above fails the
#    build with an undefined reference;
#  - at configure time, fails if a file outside core (and outside the few files listed in
#    GFMD_OPENMP_KERNELS) has an OpenMP pragma: grid passes go through the backend seam
#    (gfmd/core/backend.hpp), not around it.

set(GFMD_PARTS "")

function(gfmd_part name)
  cmake_parse_arguments(P "" "" "DEPENDS;PUBLIC;PRIVATE" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/${name}/*.cpp)
  add_library(gfmd_${name} STATIC ${sources})
  target_include_directories(gfmd_${name} PUBLIC ${CMAKE_SOURCE_DIR}/include ${CMAKE_BINARY_DIR}/generated)
  target_include_directories(gfmd_${name} PRIVATE ${CMAKE_SOURCE_DIR}/src/${name})
  target_compile_options(gfmd_${name} PRIVATE "$<$<COMPILE_LANGUAGE:CXX>:${GFMD_WARNINGS}>")
  set_target_properties(gfmd_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  set(closure "")
  foreach(dep ${P_DEPENDS})
    if(NOT TARGET gfmd_${dep})
      message(FATAL_ERROR "part '${name}' depends on '${dep}', which is not defined below it")
    endif()
    target_link_libraries(gfmd_${name} PUBLIC gfmd_${dep})
    get_property(below GLOBAL PROPERTY GFMD_PART_CLOSURE_${dep})
    list(APPEND closure ${dep} ${below})
  endforeach()
  list(REMOVE_DUPLICATES closure)
  if(P_PUBLIC)
    target_link_libraries(gfmd_${name} PUBLIC ${P_PUBLIC})
  endif()
  if(P_PRIVATE)
    target_link_libraries(gfmd_${name} PRIVATE ${P_PRIVATE})
  endif()
  set_property(GLOBAL PROPERTY GFMD_PART_CLOSURE_${name} "${closure}")
  set_property(GLOBAL APPEND PROPERTY GFMD_PARTS ${name})
endfunction()

function(gfmd_check_layers)
  get_property(parts GLOBAL PROPERTY GFMD_PARTS)
  set(main ${CMAKE_BINARY_DIR}/generated/layer_check_main.cpp)
  file(WRITE ${main} "int main() { return 0; }\n")
  set(violations "")
  foreach(name ${parts})
    get_property(allowed GLOBAL PROPERTY GFMD_PART_CLOSURE_${name})
    list(APPEND allowed ${name})
    # The CUDA sources (.cu, .cuh) are read too: they are part of their folder's part.
    file(GLOB_RECURSE files CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/include/gfmd/${name}/*.hpp
         ${CMAKE_SOURCE_DIR}/include/gfmd/${name}/*.cuh ${CMAKE_SOURCE_DIR}/src/${name}/*.hpp
         ${CMAKE_SOURCE_DIR}/src/${name}/*.cpp ${CMAKE_SOURCE_DIR}/src/${name}/*.cu
         ${CMAKE_SOURCE_DIR}/src/${name}/*.cuh)
    foreach(f ${files})
      file(RELATIVE_PATH relf ${CMAKE_SOURCE_DIR} ${f})
      if(NOT name STREQUAL "core" AND NOT relf IN_LIST GFMD_OPENMP_KERNELS)
        file(STRINGS ${f} pragmas REGEX "^[ \t]*#[ \t]*pragma[ \t]+omp")
        if(pragmas)
          list(APPEND violations "${relf}: OpenMP pragma outside core (write the loop as a backend pass: parallel_for, for_rows)")
        endif()
      endif()
      file(STRINGS ${f} includes REGEX "^[ \t]*#[ \t]*include[ \t]*[\"<]gfmd/[a-z_]+/")
      foreach(line ${includes})
        string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*[\"<]gfmd/([a-z_]+)/.*" "\\1" used "${line}")
        if(NOT used IN_LIST allowed)
          file(RELATIVE_PATH rel ${CMAKE_SOURCE_DIR} ${f})
          list(APPEND violations "${rel}: part '${name}' includes part '${used}' (allowed: ${allowed})")
        endif()
      endforeach()
    endforeach()
    # Build-time check: the part's every object with only what it declares.
    add_executable(layer_check_${name} ${main})
    target_link_libraries(layer_check_${name} PRIVATE "$<LINK_LIBRARY:WHOLE_ARCHIVE,gfmd_${name}>")
  endforeach()
  if(violations)
    list(JOIN violations "\n  " text)
    message(FATAL_ERROR "the library's layer order is broken:\n  ${text}")
  endif()
endfunction()
