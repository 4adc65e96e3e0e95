# Offline tools: train and evaluate, and the evaluation library they share.
add_library(action_flow_eval src/eval/evaluation.cpp src/eval/stream_scoring.cpp src/eval/detection_scoring.cpp)
target_link_libraries(action_flow_eval action_flow_core)

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_evaluation test/eval/test_evaluation.cpp test/eval/test_paper_variant.cpp)
  target_link_libraries(test_evaluation action_flow_eval gtest_main)
  catkin_add_gtest(test_stream_scoring test/eval/test_stream_scoring.cpp)
  target_link_libraries(test_stream_scoring action_flow_eval gtest_main)
  catkin_add_gtest(test_detection_scoring test/eval/test_detection_scoring.cpp)
  target_link_libraries(test_detection_scoring action_flow_eval gtest_main)
endif()

# The tools run the people tracker and render with the virtual Kinect.
# yaml-cpp (Debian's libyaml-cpp-dev) reads the config files for the tools' --config, as rosparam
# does for the nodelets.
find_package(yaml-cpp REQUIRED)
add_library(action_flow_tool_support
  src/eval/feature_extractor.cpp src/tools/sample_sources.cpp src/tools/extraction.cpp src/tools/param_files.cpp)
target_include_directories(action_flow_tool_support SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
target_link_libraries(action_flow_tool_support action_flow_eval action_flow_tracker action_flow_synth action_flow_ros
  ${catkin_LIBRARIES} ${OpenCV_LIBRARIES} yaml-cpp Boost::program_options pthread)

foreach(tool train evaluate)
  add_executable(${tool} src/tools/${tool}.cpp)
  if(tool STREQUAL "evaluate")
    target_sources(${tool} PRIVATE src/tools/online_protocol.cpp src/tools/detection_protocol.cpp)
  endif()
  target_include_directories(${tool} SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
  target_link_libraries(${tool} action_flow_tool_support ${catkin_LIBRARIES} ${OpenCV_LIBRARIES})
  target_compile_definitions(${tool} PRIVATE ACTION_FLOW_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endforeach()

# record: a sample of your own from the live driver, in the virtual Kinect's bag layout (record.launch).
add_executable(record src/tools/record.cpp)
target_link_libraries(record action_flow_synth_bag ${catkin_LIBRARIES} Boost::program_options)

# The tools and the libraries they (and bench, cmake/bench.cmake) load at run time.
install(TARGETS action_flow_eval action_flow_tool_support train evaluate record
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_tools test/eval/test_tools.cpp TIMEOUT 600)
  target_link_libraries(test_tools action_flow_core gtest_main)
  target_compile_definitions(test_tools PRIVATE
    ACTION_FLOW_BIN_DIR="${CATKIN_DEVEL_PREFIX}/lib/action_flow"
    ACTION_FLOW_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  add_dependencies(test_tools train evaluate synth)
  catkin_add_gtest(test_params test/eval/test_params.cpp)
  target_link_libraries(test_params action_flow_tool_support gtest_main)
  target_compile_definitions(test_params PRIVATE ACTION_FLOW_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
endif()
