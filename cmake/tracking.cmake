# Several people at once (issue 15): tracking measured as the MOT benchmarks measure it. The metrics
# (ROS-free, on the tracker's assignment solver), the evaluate_tracking tool on crowd scenes of the
# virtual Kinect, and their tests: the metrics on hand-made known answers, crossing people through
# the real tracker, the crowd scenes' ground truth.
add_library(action_flow_tracking_eval src/eval/tracking_metrics.cpp)
target_link_libraries(action_flow_tracking_eval action_flow_tracker)

add_executable(evaluate_tracking src/tools/evaluate_tracking.cpp)
target_link_libraries(evaluate_tracking action_flow_tracking_eval action_flow_tool_support ${catkin_LIBRARIES})
target_compile_definitions(evaluate_tracking PRIVATE ACTION_FLOW_SOURCE_DIR="${PROJECT_SOURCE_DIR}")

install(TARGETS action_flow_tracking_eval evaluate_tracking
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_tracking
    test/eval/test_tracking_metrics.cpp
    test/tracker/test_tracker_crossing.cpp
    test/synth/test_crowd.cpp)
  target_link_libraries(test_tracking action_flow_tracking_eval action_flow_tracker action_flow_synth gtest_main)
endif()
