# bench: per-stage timings against the paper's Table 2 and a PCL-octree baseline (docs/bench.md).
add_library(action_flow_bench STATIC
  src/bench/moving_person.cpp
  src/bench/octree_flow_baseline.cpp
  src/bench/training_set.cpp)
target_link_libraries(action_flow_bench action_flow_core ${PCL_LIBRARIES})

add_executable(bench src/tools/bench.cpp)
target_link_libraries(bench action_flow_bench action_flow_core)

install(TARGETS bench RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
