# bench: per-stage timings against the paper's Table 2 and a PCL-octree baseline (docs/bench.md).
add_library(action_flow_bench STATIC
  src/bench/octree_flow_baseline.cpp
  src/bench/training_set.cpp)
target_link_libraries(action_flow_bench action_flow_core ${PCL_LIBRARIES})

add_executable(bench src/tools/bench.cpp)
target_link_libraries(bench action_flow_bench action_flow_core Boost::program_options)

install(TARGETS bench RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # The benchmark's parts (statistics, the octree baseline agreeing with the core, the generated
  # descriptor sequences).
  catkin_add_gtest(test_bench test/bench/test_bench_parts.cpp)
  target_link_libraries(test_bench action_flow_bench action_flow_core gtest_main)
endif()

# The benchmark takes its frames from the virtual Kinect, times the people tracker, and classifies
# real frame descriptors (an evaluate cache folder, --descriptors).
target_link_libraries(bench action_flow_synth action_flow_tracker action_flow_eval)

# The whole pipeline through the nodelet manager (docs/bench.md): a player nodelet that feeds
# in-memory synthetic frames to depth_image_proc and the stages in the same manager and measures
# fps, CPU, latency and memory.
# Depth image to cloud: depth_image_proc's conversion (the live path, then the tracker's check
# and copy) beside the tools' own depthToCloud, on the same frame.
find_package(image_geometry REQUIRED)
target_include_directories(bench SYSTEM PRIVATE ${image_geometry_INCLUDE_DIRS})
target_link_libraries(bench action_flow_ros ${image_geometry_LIBRARIES})
add_library(action_flow_bench_nodelet src/bench/bench_player_nodelet.cpp)
target_link_libraries(action_flow_bench_nodelet action_flow_ros ${catkin_LIBRARIES})
install(TARGETS action_flow_bench_nodelet
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  roslaunch_add_file_check(launch/bench_pipeline.launch bags:=a.bag model:=a.model output:=out)

  # A short closed-loop run of the same launch on one small synthetic bag (40 frames, looped).
  set(ACTION_FLOW_BENCH_BAG ${CMAKE_BINARY_DIR}/bench_pipeline_bag/ias/p01_wave_1.bag)
  add_custom_command(OUTPUT ${ACTION_FLOW_BENCH_BAG}
    COMMAND synth --out ${CMAKE_BINARY_DIR}/bench_pipeline_bag --people 1 --person p01 --action wave
            --repetitions 1 --frames 40 --raw-images --quiet
    DEPENDS synth
    COMMENT "Rendering the whole-pipeline benchmark's test bag")
  add_custom_target(action_flow_bench_bag DEPENDS ${ACTION_FLOW_BENCH_BAG})
  add_executable(test_bench_pipeline EXCLUDE_FROM_ALL test/bench/test_bench_pipeline.cpp)
  target_link_libraries(test_bench_pipeline ${catkin_LIBRARIES} gtest)
  add_dependencies(tests test_bench_pipeline action_flow_bench_bag action_flow_bench_nodelet)
  add_rostest(test/bench/bench_pipeline.test
    ARGS bag:=${ACTION_FLOW_BENCH_BAG} model:=${CMAKE_BINARY_DIR}/test_models/posture_flow.afm
         output:=${CMAKE_BINARY_DIR}/bench_pipeline_test
    DEPENDENCIES test_bench_pipeline action_flow_bench_bag action_flow_test_models)
endif()
