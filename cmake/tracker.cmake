# People tracker core (ROS-free): its own library on top of action_flow_core and PCL's people module.
# PCL's people component (it brings VTK through PCL's visualization) is looked up here, for the
# tracker only, with the top CMakeLists' components again so that none is dropped; PCL_LIBRARIES is
# restored afterwards so that the parts included after this one see what the top CMakeLists found.
set(_action_flow_pcl_libraries ${PCL_LIBRARIES})
find_package(PCL REQUIRED COMPONENTS common kdtree octree search filters segmentation sample_consensus io people)
set(ACTION_FLOW_PCL_PEOPLE_LIBRARIES ${PCL_LIBRARIES})
set(PCL_LIBRARIES ${_action_flow_pcl_libraries})

add_library(action_flow_tracker
  src/core/people_tracker.cpp
  src/core/tracker_detector.cpp
  src/core/tracker_ground.cpp
  src/core/tracker_assignment.cpp
  src/core/tracker_clustering.cpp
  src/core/tracker_walls.cpp
)
target_link_libraries(action_flow_tracker action_flow_core ${ACTION_FLOW_PCL_PEOPLE_LIBRARIES} ${PCL_LIBRARIES})

# PCL's trained HOG+SVM person classifier (hog_classifier_file "default"): Debian's libpcl-dev lacks
# it, the shared data folder has it. Installed into the package's share/data/ when present at
# configure time; the library looks there, then in the source tree's ../shared/data/pcl_people/.
set(ACTION_FLOW_HOG_FILE_NAME trainedLinearSVMForPeopleDetectionWithHOG.yaml)
set(ACTION_FLOW_HOG_SOURCE_FILE ${PROJECT_SOURCE_DIR}/../shared/data/pcl_people/${ACTION_FLOW_HOG_FILE_NAME})
target_compile_definitions(action_flow_tracker PRIVATE
  ACTION_FLOW_HOG_INSTALLED="${CMAKE_INSTALL_PREFIX}/${CATKIN_PACKAGE_SHARE_DESTINATION}/data/${ACTION_FLOW_HOG_FILE_NAME}"
  ACTION_FLOW_HOG_SOURCE="${ACTION_FLOW_HOG_SOURCE_FILE}")
# The file lies outside the package: its copy in the build folder (made when CMake generates) is
# what gets installed.
if(EXISTS "${ACTION_FLOW_HOG_SOURCE_FILE}")
  file(GENERATE OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/data/${ACTION_FLOW_HOG_FILE_NAME} INPUT ${ACTION_FLOW_HOG_SOURCE_FILE})
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/data/${ACTION_FLOW_HOG_FILE_NAME}
          DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/data)
endif()

# Benchmark: per-frame time on the real 640x480 clouds (reads bags, so it links catkin's rosbag).
# A development aid of the test tree that reads the source tree's ../shared/data: built (as
# devel/lib/action_flow/tracker_benchmark), not installed; its target is named as a test's.
add_executable(test_tracker_benchmark test/tracker/tracker_benchmark.cpp)
set_target_properties(test_tracker_benchmark PROPERTIES OUTPUT_NAME tracker_benchmark)
target_compile_definitions(test_tracker_benchmark PRIVATE ACTION_FLOW_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/data")
target_link_libraries(test_tracker_benchmark action_flow_tracker ${catkin_LIBRARIES} Boost::program_options)

install(TARGETS action_flow_tracker
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  catkin_add_gtest(test_tracker
    test/tracker/test_tracker_parts.cpp
    test/tracker/test_tracker_scenes.cpp
    test/tracker/test_tracker_real.cpp
    test/tracker/test_tracker_likeness.cpp
    test/tracker/test_tracker_clutter.cpp)
  target_compile_definitions(test_tracker PRIVATE
    ACTION_FLOW_DATA_DIR="${PROJECT_SOURCE_DIR}/../shared/data"
    ACTION_FLOW_TRACKER_TEST_DIR="${PROJECT_SOURCE_DIR}/test/tracker")
  target_link_libraries(test_tracker action_flow_tracker action_flow_synth ${catkin_LIBRARIES} gtest_main)
endif()
