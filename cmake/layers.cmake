# Layers the build enforces. Every folder of the project is one library
# target, and sources include headers by their path from the project root
# ("kernels/scene/scene.h"). A target's include root is a directory of the
# build tree that holds a link to its own folder only, so a path resolves in
# a target only if that target links the library of the folder: an include
# that climbs a layer, or reaches across to one not linked, fails to compile
# (tests/layering checks that it does).

# Gives TARGET the include root that exposes FOLDER (relative to the project
# root), to itself and, through PUBLIC / INTERFACE, to what links it.
function(pt_layer target folder)
  set(root ${PROJECT_BINARY_DIR}/layers/${target})
  get_filename_component(parent ${root}/${folder} DIRECTORY)
  file(MAKE_DIRECTORY ${parent})
  if(NOT EXISTS ${root}/${folder})
    file(CREATE_LINK ${PROJECT_SOURCE_DIR}/${folder} ${root}/${folder} SYMBOLIC)
  endif()
  get_target_property(type ${target} TYPE)
  if(type STREQUAL "INTERFACE_LIBRARY")
    target_include_directories(${target} INTERFACE ${root})
  else()
    target_include_directories(${target} PUBLIC ${root})
  endif()
  set_property(TARGET ${target} PROPERTY PT_LAYER_ROOT ${root})
endfunction()
