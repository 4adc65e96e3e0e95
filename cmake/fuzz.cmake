# Fuzz suite (hardening): generators of malformed inputs, deterministic from a seed, and a bounded
# corpus run in CI (about 2,000 inputs, a few minutes): in-process checks and file readers, the
# tools as processes, and the real nodelet manager under bad messages. The long mode
# (ACTION_FLOW_FUZZ_INPUTS=20000, or scripts/fuzz --inputs 20000) runs the same tests scaled up.
if(CATKIN_ENABLE_TESTING)
  add_library(action_flow_fuzz STATIC test/fuzz/generators.cpp test/fuzz/harness.cpp)
  target_link_libraries(action_flow_fuzz action_flow_core ${catkin_LIBRARIES})
  add_dependencies(action_flow_fuzz ${catkin_EXPORTED_TARGETS})

  # In-process: messages against the input checks and the tracker core, bags through the tools'
  # reader and pipeline, models, index CSVs, MSR skeletons.
  catkin_add_gtest(test_fuzz_inputs test/fuzz/test_fuzz_inputs.cpp TIMEOUT 600)
  target_link_libraries(test_fuzz_inputs action_flow_fuzz action_flow_tool_support action_flow_ros gtest_main)

  # The tools as processes: bad command lines, bags, indexes and skeletons.
  catkin_add_gtest(test_fuzz_tools test/fuzz/test_fuzz_tools.cpp TIMEOUT 900)
  target_link_libraries(test_fuzz_tools action_flow_fuzz gtest_main)
  target_compile_definitions(test_fuzz_tools PRIVATE ACTION_FLOW_BIN_DIR="${CATKIN_DEVEL_PREFIX}/lib/action_flow")
  add_dependencies(test_fuzz_tools train evaluate synth)

  # The real manager: generated bad clouds to the people tracker, bad images and camera_info through
  # the image guard to depth_image_proc, then good frames, which must still be served.
  add_executable(test_fuzz_manager EXCLUDE_FROM_ALL test/fuzz/test_fuzz_manager.cpp)
  target_link_libraries(test_fuzz_manager action_flow_fuzz action_flow_ros ${catkin_LIBRARIES} gtest)
  add_dependencies(test_fuzz_manager ${PROJECT_NAME}_generate_messages_cpp)
  add_dependencies(tests test_fuzz_manager)
  add_rostest(test/fuzz/fuzz_manager.test DEPENDENCIES test_fuzz_manager)
endif()
