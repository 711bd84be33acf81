# The layers of valerant, lowest first: the one place their order is written.
#
# Each layer is a directory pair include/valerant/<layer>, src/<layer> and one shared
# library that links the layer just below it (so every lower one): valerant_core_<layer>
# for the ROS-free layers (the tools are valerant_<name>), valerant_ros for ros. A
# layer may include its own headers and those of lower layers only:
# test/layers/check_layers.py, run by scripts/test with this list, fails on any other
# include, and -Wl,--no-undefined makes the linker refuse a library that calls upward.
#   common    errors, camera model, output files, trajectories
#   config    the typed configuration (yaml)
#   world     world models: the Quake III engine backend, action sequences
#   slam      SLAM backends (visual, oracle) and the ground-truth source the oracle reads
#   geometry  what map and explore share: the floor plane and the exploration grid
#   map       map fusion, frames, exports, meshes, a run's saved map
#   explore   the branch pipeline, collision checks, policy, the episode loop
#   eval      ground-truth evaluation of episodes, run directories, grids, reports
#   dataset   training shards for the learned parts
#   ros       the ROS adapters (proxies, conversions, the bag world) under the nodes
# Nodes (src/nodes) and tools (src/tools) are on top and link the layer they need.
set(VALERANT_LAYERS common config world slam geometry map explore eval dataset ros)

# The ROS-free libraries (every layer below ros), as catkin exports and installs them.
set(VALERANT_LIBRARIES)
foreach(layer IN LISTS VALERANT_LAYERS)
  if(NOT layer STREQUAL "ros")
    list(APPEND VALERANT_LIBRARIES valerant_core_${layer})
  endif()
endforeach()

# Makes the library of every layer from src/<layer> (subfolders included), each linking
# the one below it. Layer-specific dependencies are added by the caller.
function(valerant_add_layer_libraries)
  set(below "")
  foreach(layer IN LISTS VALERANT_LAYERS)
    if(layer STREQUAL "ros")
      set(library valerant_ros)
    else()
      set(library valerant_core_${layer})
    endif()
    file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/src/${layer}/*.cpp)
    add_library(${library} ${sources})
    target_include_directories(${library} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include)
    # A shared library must resolve every symbol in the layers it links: a call into a
    # higher layer fails here, at link time, not in the program that loads it.
    target_link_options(${library} PRIVATE -Wl,--no-undefined)
    if(below)
      target_link_libraries(${library} PUBLIC ${below})
    endif()
    set(below ${library})
  endforeach()
endfunction()
