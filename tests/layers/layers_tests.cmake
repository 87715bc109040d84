# The layers of src/ point one way (src/CMakeLists.txt). Each check compiles a
# one-line source, `#include <HEADER>`, with the include directories that
# TARGET's own sources get, and so shows whether TARGET's code can include
# HEADER at all: a layer below must not find the headers of a layer above. A
# check that expects a header to be missing passes only on the compiler's
# "not found" for that header, so that an unrelated failure does not pass it;
# one that expects it found keeps the forbidden checks honest.
function(fretsim_layer_check target header expectation)
  string(MAKE_C_IDENTIFIER "${target}_${header}" name)
  set(source ${CMAKE_CURRENT_BINARY_DIR}/layers/${name}.cpp)
  file(WRITE ${source} "#include <${header}>\n")
  set(test layers.${target}.${expectation}.${header})
  add_test(NAME ${test}
    COMMAND ${CMAKE_CXX_COMPILER} -std=c++17 -fsyntax-only
            "-I$<JOIN:$<TARGET_PROPERTY:${target},INCLUDE_DIRECTORIES>,;-I>" ${source}
    COMMAND_EXPAND_LISTS)
  set_tests_properties(${test} PROPERTIES LABELS unit)
  if(expectation STREQUAL "cannot_see")
    string(REPLACE "." "\\." pattern "${header}")
    set_tests_properties(${test} PROPERTIES
      PASS_REGULAR_EXPRESSION "${pattern}'?:? (No such file or directory|file not found)")
  elseif(NOT expectation STREQUAL "sees")
    message(FATAL_ERROR "fretsim_layer_check: expectation is sees or cannot_see, not ${expectation}")
  endif()
endfunction()

# The commands and the CLI are the top: nothing below sees them.
fretsim_layer_check(fretsim_scenes app/cli.h cannot_see)
fretsim_layer_check(fretsim_models app/cli.h cannot_see)
fretsim_layer_check(fretsim_support app/cli.h cannot_see)
fretsim_layer_check(fretsim_output app/cli.h cannot_see)
fretsim_layer_check(fretsim_coupling app/cli.h cannot_see)
# The scenes are above the models and the support, not below.
fretsim_layer_check(fretsim_models fretsim/scenes/scene.h cannot_see)
fretsim_layer_check(fretsim_support fretsim/scenes/scene.h cannot_see)
fretsim_layer_check(fretsim_support fretsim/models/ring_housing.h cannot_see)
# What each layer does use is found.
fretsim_layer_check(fretsim_scenes fretsim/support/parameters.h sees)
fretsim_layer_check(fretsim_scenes fretsim/output/results_file.h sees)
fretsim_layer_check(fretsim_app fretsim/scenes/scene.h sees)
fretsim_layer_check(fretsim_app app/cli.h sees)
