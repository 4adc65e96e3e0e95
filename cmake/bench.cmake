# bench: per-stage timings against the paper's Table 2 and a PCL-octree baseline (docs/bench.md).
add_library(action_flow_bench STATIC
  src/bench/moving_person.cpp
  src/bench/octree_flow_baseline.cpp
  src/bench/training_set.cpp)
target_link_libraries(action_flow_bench action_flow_core ${PCL_LIBRARIES})

add_executable(bench src/tools/bench.cpp)
target_link_libraries(bench action_flow_bench action_flow_core)

install(TARGETS bench RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # Exactness of the flow's grid index and matcher against nanoflann and brute force, and the
  # benchmark's parts (statistics, generated person, octree baseline agreeing with the core).
  catkin_add_gtest(test_bench
    test/bench/test_neighbour_grid.cpp
    test/bench/test_bench_parts.cpp)
  target_link_libraries(test_bench action_flow_bench action_flow_core gtest_main)
endif()

# The benchmark takes its frames from the virtual Kinect and times the people tracker when those
# parts are in the tree; without them it uses its own generated person and skips the tracker.
if(TARGET action_flow_synth)
  target_compile_definitions(bench PRIVATE ACTION_FLOW_BENCH_SYNTH)
  target_link_libraries(bench action_flow_synth)
endif()
if(TARGET action_flow_tracker)
  target_compile_definitions(bench PRIVATE ACTION_FLOW_BENCH_TRACKER)
  target_link_libraries(bench action_flow_tracker)
endif()
# Classification on real frame descriptors (an evaluate cache folder, --descriptors).
if(TARGET action_flow_eval)
  target_compile_definitions(bench PRIVATE ACTION_FLOW_BENCH_EVAL)
  target_link_libraries(bench action_flow_eval)
endif()
