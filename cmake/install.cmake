# Install rules: `cmake --install BUILD --prefix PREFIX` (or `make install` with
# CMAKE_INSTALL_PREFIX) gives a catkin install space that runs without the source tree:
# source PREFIX/setup.bash, then the tools are on PATH, `rosrun valerant NODE` and
# `roslaunch valerant explore.launch` work, and the core finds config/ and models/ in
# PREFIX/share/valerant (include/valerant/config/package_dir.h). catkin itself installs
# package.xml, the setup files, the CMake/pkg-config files and, through
# generate_messages, the msg/srv/action files and the generated C++ and Python code.

# The ROS-free core is one library per layer (VALERANT_LIBRARIES, cmake/valerant_layers.cmake).
install(TARGETS ${VALERANT_LIBRARIES} valerant_ros valerant_nodelets
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})

# Nodes where roslaunch and rosrun look for them (lib/valerant).
install(TARGETS world_model_server policy_arbiter map_fusion explorer run_publisher
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

# The command-line tools are what a user types: on PATH (bin) once setup.bash is sourced.
install(TARGETS valerant_render valerant_explore valerant_slam valerant_eval valerant_export valerant_dataset
  valerant_bench
  RUNTIME DESTINATION ${CATKIN_GLOBAL_BIN_DESTINATION})

# Headers of the libraries above (catkin_package exports INCLUDE_DIRS include).
install(DIRECTORY include/valerant/ DESTINATION ${CATKIN_PACKAGE_INCLUDE_DESTINATION})

# Run-time files, found through the package folder: the nodelet plugin description
# (package.xml exports it), the configuration, launch files with their parameters and
# distributed.launch's env-loader, the rviz view and the learned depth prior.
install(FILES nodelet_plugins.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(DIRECTORY config rviz models DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(DIRECTORY launch DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}
  PATTERN "*.sh" PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ
  WORLD_EXECUTE)

# valerant_eval's plotting script (include/valerant/eval/eval_plots.h), run by Debian's
# python3 with python3-matplotlib.
install(PROGRAMS scripts/plot_eval.py DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/scripts)
