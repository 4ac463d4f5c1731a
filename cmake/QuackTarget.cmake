# quack_add_layer(NAME SOURCES ... DEPENDS ...): one library per layer, exported as
# quack::NAME. Warnings are PRIVATE so that they never leak into a consumer's build.
set(QUACK_LAYERS "" CACHE INTERNAL "Quack's layer targets, in dependency order")

function(quack_set_warnings target)
  if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
    target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow -Wconversion
                                             -Wno-sign-conversion -Wdouble-promotion
                                             -Wnon-virtual-dtor -Wold-style-cast
                                             # Designated initializers that leave defaulted
                                             # members out are how BodyDef and friends are
                                             # meant to be filled; GCC 12 warns regardless
                                             # (GCC bug 96868).
                                             -Wno-missing-field-initializers)
    if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
      # GCC 12 reports a false -Wrestrict inside libstdc++'s std::string operator+ at -O2
      # (GCC bug 105651, fixed in 13); our code has no restrict-qualified pointers.
      target_compile_options(${target} PRIVATE -Wno-restrict)
    endif()
    if(QUACK_WARNINGS_AS_ERRORS)
      target_compile_options(${target} PRIVATE -Werror)
    endif()
  endif()
endfunction()

function(quack_add_layer name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPENDS" ${ARGN})
  set(target quack_${name})
  if(ARG_SOURCES)
    add_library(${target} ${ARG_SOURCES})
    set(scope PUBLIC)
    set_target_properties(${target} PROPERTIES OUTPUT_NAME quack_${name} POSITION_INDEPENDENT_CODE ON)
    quack_set_warnings(${target})
    if(CMAKE_CXX_COMPILER_ID MATCHES "GNU|Clang")
      # Determinism (docs/world.md): no fused multiply-add contracted behind our back, so
      # that every build (and every SIMD path) rounds the same operations the same way.
      target_compile_options(${target} PRIVATE -ffp-contract=off)
    endif()
  else()
    # A header-only layer; the tests compile its headers with the warnings on.
    add_library(${target} INTERFACE)
    set(scope INTERFACE)
  endif()
  add_library(quack::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
  target_compile_features(${target} ${scope} cxx_std_20)
  target_include_directories(${target} ${scope} $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
                                                $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} ${scope} ${ARG_DEPENDS})
  if(QUACK_ENABLE_ASSERTS)
    target_compile_definitions(${target} ${scope} QUACK_ENABLE_ASSERTS)
  endif()
  set(QUACK_LAYERS ${QUACK_LAYERS} ${target} CACHE INTERNAL "")
endfunction()
