# Compile options for shapepress's own targets only: third-party headers come in through imported
# targets, whose include directories CMake marks SYSTEM, so -Werror never trips on them.
add_library(shapepress_options INTERFACE)
target_compile_options(shapepress_options INTERFACE -Wall -Wextra -Wpedantic)
if(SHAPEPRESS_WERROR)
  target_compile_options(shapepress_options INTERFACE -Werror)
endif()
if(SHAPEPRESS_NATIVE)
  target_compile_options(shapepress_options INTERFACE -march=native)
endif()
if(SHAPEPRESS_SANITIZE)
  target_compile_options(shapepress_options INTERFACE -fsanitize=address,undefined
                                                      -fno-omit-frame-pointer -fno-sanitize-recover=all)
  target_link_options(shapepress_options INTERFACE -fsanitize=address,undefined)
endif()
if(SHAPEPRESS_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "SHAPEPRESS_FUZZ needs clang (libFuzzer): -DCMAKE_CXX_COMPILER=clang++")
  endif()
  # Coverage for libFuzzer in all of shapepress's code; the fuzz targets link the fuzzer's main.
  target_compile_options(shapepress_options INTERFACE -fsanitize=fuzzer-no-link,address
                                                      -fno-omit-frame-pointer)
  target_link_options(shapepress_options INTERFACE -fsanitize=address)
endif()
# Release builds take CMake's own flags (GCC and Clang: -O3 -DNDEBUG; a user's
# CMAKE_CXX_FLAGS_RELEASE replaces them): no -march, so the binary runs on any x86-64
# (SHAPEPRESS_NATIVE=ON tunes it).
target_include_directories(shapepress_options INTERFACE ${CMAKE_SOURCE_DIR} ${CMAKE_BINARY_DIR}/generated)

# shapepress_add_library(name SOURCES…): one library per stage folder.
function(shapepress_add_library name)
  add_library(${name} STATIC ${ARGN})
  target_link_libraries(${name} PUBLIC shapepress_options)
  set_target_properties(${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
endfunction()
