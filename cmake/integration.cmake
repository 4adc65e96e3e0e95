# The whole pipeline as a user runs it: train, synth and roslaunch with rosbag play.
if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_pipeline_bags test/integration/test_pipeline_bags.cpp TIMEOUT 900)
  target_link_libraries(test_pipeline_bags gtest_main)
  target_compile_definitions(test_pipeline_bags PRIVATE
    ACTION_FLOW_BIN_DIR="${CATKIN_DEVEL_PREFIX}/lib/action_flow"
    ACTION_FLOW_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  add_dependencies(test_pipeline_bags train synth record)
endif()
