# The virtual Kinect and synthetic actors (issue 3): ROS-free rendering library, the `synth`
# executable (bags, previews) and their tests.
# OpenCV (core imgproc imgcodecs) is found by the top CMakeLists.

add_library(action_flow_synth
  src/synth/skeleton.cpp
  src/synth/scene.cpp
  src/synth/motion.cpp
  src/synth/samples.cpp
  src/synth/stream.cpp
  src/synth/crowd.cpp
  src/synth/clutter.cpp
)
target_link_libraries(action_flow_synth action_flow_core ${PCL_LIBRARIES})

# Bag writing and image encoding, shared by the executable and its tests.
add_library(action_flow_synth_bag src/tools/synth_bag.cpp)
target_include_directories(action_flow_synth_bag SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
target_link_libraries(action_flow_synth_bag action_flow_synth ${catkin_LIBRARIES} ${OpenCV_LIBRARIES})
add_dependencies(action_flow_synth_bag ${catkin_EXPORTED_TARGETS})

add_executable(synth src/tools/synth.cpp)
target_link_libraries(synth action_flow_synth_bag action_flow_synth Boost::program_options pthread)

install(TARGETS action_flow_synth action_flow_synth_bag synth
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_synth
    test/synth/test_scene.cpp
    test/synth/test_samples.cpp
    test/synth/test_stream.cpp
    test/synth/test_clutter.cpp)
  target_link_libraries(test_synth action_flow_synth gtest_main)
  target_compile_definitions(test_synth PRIVATE
    ACTION_FLOW_SHARED_DATA="${PROJECT_SOURCE_DIR}/../shared/data")

  catkin_add_gtest(test_synth_bag test/synth/test_synth_bag.cpp)
  target_link_libraries(test_synth_bag action_flow_synth_bag action_flow_synth gtest_main)
endif()
