# Offline tools: train and evaluate, and the evaluation library they share.
add_library(action_flow_eval
  src/eval/evaluation.cpp
  src/eval/feature_extractor.cpp
  src/eval/depth_cloud.cpp)
target_link_libraries(action_flow_eval action_flow_core action_flow_tracker)

add_library(action_flow_tool_support src/tools/sample_sources.cpp src/tools/extraction.cpp)
target_link_libraries(action_flow_tool_support action_flow_eval ${catkin_LIBRARIES} pthread)
if(TARGET action_flow_synth)
  target_link_libraries(action_flow_tool_support action_flow_synth)
endif()

foreach(tool train evaluate)
  add_executable(${tool} src/tools/${tool}.cpp)
  target_link_libraries(${tool} action_flow_tool_support ${catkin_LIBRARIES})
  target_compile_definitions(${tool} PRIVATE ACTION_FLOW_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endforeach()

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_evaluation test/eval/test_evaluation.cpp)
  target_link_libraries(test_evaluation action_flow_eval gtest_main)
endif()
