# ROS wrappers: the pipeline's nodelets, their test aids, launch checks and rostests.
find_package(PkgConfig REQUIRED)
pkg_check_modules(OPENNI2 REQUIRED libopenni2)
# libfreenect: its header at build time; the library itself is loaded when a Kinect v1 or a
# fakenect dump is opened (src/driver/freenect_device.h), the replay library from fakenect's folder.
pkg_check_modules(FREENECT REQUIRED libfreenect)
find_file(ACTION_FLOW_FAKENECT_LIBRARY libfreenect.so.0.5
          PATHS /usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/fakenect /usr/lib/fakenect NO_DEFAULT_PATH)
# OpenCV (core imgproc imgcodecs) is found by the top CMakeLists.

# Stage types (zero-copy message traits) and parameter reading, shared by every nodelet.
add_library(action_flow_ros src/nodelets/stage_types.cpp src/nodelets/params.cpp src/nodelets/input_checks.cpp
  src/nodelets/stage_diagnostics.cpp)
add_dependencies(action_flow_ros ${PROJECT_NAME}_generate_messages_cpp)
find_package(ZLIB REQUIRED)
target_link_libraries(action_flow_ros action_flow_core ${catkin_LIBRARIES} ZLIB::ZLIB)

# Flow, descriptor and classifier stages, the image guard and the annotator (OpenCV draws).
add_library(action_flow_nodelets
  src/nodelets/flow_nodelet.cpp
  src/nodelets/descriptor_nodelet.cpp
  src/nodelets/classifier_nodelet.cpp
  src/nodelets/image_guard_nodelet.cpp
  src/nodelets/annotator_nodelet.cpp)
target_include_directories(action_flow_nodelets SYSTEM PRIVATE ${OpenCV_INCLUDE_DIRS})
target_link_libraries(action_flow_nodelets action_flow_ros ${OpenCV_LIBRARIES})

# Driver: OpenNI2 and libfreenect backends.
add_library(action_flow_devices src/driver/openni2_device.cpp src/driver/freenect_device.cpp)
target_include_directories(action_flow_devices SYSTEM PRIVATE ${OPENNI2_INCLUDE_DIRS} ${FREENECT_INCLUDE_DIRS})
target_link_libraries(action_flow_devices ${OPENNI2_LIBRARIES} ${CMAKE_DL_LIBS})
if(ACTION_FLOW_FAKENECT_LIBRARY)
  target_compile_definitions(action_flow_devices PRIVATE ACTION_FLOW_FAKENECT_LIBRARY="${ACTION_FLOW_FAKENECT_LIBRARY}")
endif()
add_library(action_flow_driver src/nodelets/driver_nodelet.cpp)
target_link_libraries(action_flow_driver action_flow_devices action_flow_ros ${catkin_LIBRARIES})

# People tracker stage, over the tracker part's core library.
add_library(action_flow_tracker_nodelet src/nodelets/people_tracker_nodelet.cpp)
target_link_libraries(action_flow_tracker_nodelet action_flow_ros action_flow_tracker ${catkin_LIBRARIES})

# Test aids (in the devel space's nodelets.xml so that rostests can load them by name; not
# installed, and left out of the installed nodelets.xml, cmake/install.cmake): a scene /
# person-cloud publisher and the zero-copy probe.
add_library(action_flow_test_nodelets test/ros/test_scene_publisher.cpp test/ros/zero_copy_probe.cpp)
target_link_libraries(action_flow_test_nodelets action_flow_ros ${catkin_LIBRARIES})

install(TARGETS action_flow_ros action_flow_nodelets action_flow_devices action_flow_driver action_flow_tracker_nodelet
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(DIRECTORY launch config rviz DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # rostest and roslaunch are found by the top CMakeLists.
  # Every launch file parses, its args resolve, and every package it names exists.
  roslaunch_add_file_check(launch/pipeline.launch)
  roslaunch_add_file_check(launch/kinect.launch)
  roslaunch_add_file_check(launch/record.launch person:=alice action:=wave)
  # One check per file (the test is named after it): the variant that names the most packages,
  # with the bag player and depth_image_proc.
  roslaunch_add_file_check(launch/bag.launch input:=images bag:=recording.bag)

  # The classifier's test models, written through the core's ActionModel::save.
  add_executable(make_test_model EXCLUDE_FROM_ALL test/ros/make_test_model.cpp)
  target_link_libraries(make_test_model action_flow_core)
  set(ACTION_FLOW_TEST_MODELS ${CMAKE_BINARY_DIR}/test_models)
  add_custom_command(OUTPUT ${ACTION_FLOW_TEST_MODELS}/two_actions.afm ${ACTION_FLOW_TEST_MODELS}/corrupt.afm
    COMMAND ${CMAKE_COMMAND} -E make_directory ${ACTION_FLOW_TEST_MODELS}
    COMMAND make_test_model ${ACTION_FLOW_TEST_MODELS}
    DEPENDS make_test_model
    COMMENT "Writing the classifier's test models")
  add_custom_target(action_flow_test_models DEPENDS ${ACTION_FLOW_TEST_MODELS}/two_actions.afm)
  add_dependencies(tests action_flow_test_models)

  # The driver's device side: the libfreenect backend on fakenect dumps (no hardware), device stamps.
  catkin_add_gtest(test_devices test/driver/test_devices.cpp)
  target_link_libraries(test_devices action_flow_devices gtest_main)

  catkin_add_gtest(test_input_checks test/ros/test_input_checks.cpp)
  target_link_libraries(test_input_checks action_flow_ros gtest_main)

  add_executable(test_load_all EXCLUDE_FROM_ALL test/ros/test_load_all.cpp)
  target_link_libraries(test_load_all ${catkin_LIBRARIES} gtest)
  add_executable(test_stages EXCLUDE_FROM_ALL test/ros/test_stages.cpp)
  target_link_libraries(test_stages action_flow_ros ${catkin_LIBRARIES} gtest)
  add_executable(test_real_data EXCLUDE_FROM_ALL test/ros/test_real_data.cpp)
  target_link_libraries(test_real_data ${catkin_LIBRARIES} ${PCL_LIBRARIES} gtest)
  add_dependencies(test_real_data ${PROJECT_NAME}_generate_messages_cpp)
  add_executable(test_annotator EXCLUDE_FROM_ALL test/ros/test_annotator.cpp)
  target_link_libraries(test_annotator action_flow_ros ${catkin_LIBRARIES} gtest)
  # The nodelet chain against the offline extraction (the tool support library's extractSample).
  add_executable(test_chain EXCLUDE_FROM_ALL test/ros/test_chain.cpp)
  target_link_libraries(test_chain action_flow_tool_support action_flow_ros ${catkin_LIBRARIES} gtest)
  add_dependencies(tests test_load_all test_stages test_real_data test_annotator test_chain)

  set(ACTION_FLOW_MODEL_ARGS model:=${ACTION_FLOW_TEST_MODELS}/two_actions.afm
                             corrupt_model:=${ACTION_FLOW_TEST_MODELS}/corrupt.afm)
  add_rostest(test/ros/load_all.test DEPENDENCIES test_load_all)
  add_rostest(test/ros/tracker.test DEPENDENCIES test_stages)
  add_rostest(test/ros/tracker_fixed_frame.test DEPENDENCIES test_stages)
  add_rostest(test/ros/tracker_bad_input.test DEPENDENCIES test_stages)
  add_rostest(test/ros/flow.test DEPENDENCIES test_stages)
  add_rostest(test/ros/chain.test DEPENDENCIES test_chain)
  add_rostest(test/ros/flow_reset.test DEPENDENCIES test_stages)
  add_rostest(test/ros/flow_bad_input.test DEPENDENCIES test_stages)
  add_rostest(test/ros/descriptor.test DEPENDENCIES test_stages)
  add_rostest(test/ros/image_guard.test DEPENDENCIES test_stages)
  add_rostest(test/ros/classifier_segmented.test ARGS ${ACTION_FLOW_MODEL_ARGS} DEPENDENCIES test_stages action_flow_test_models)
  add_rostest(test/ros/classifier_online.test ARGS ${ACTION_FLOW_MODEL_ARGS} DEPENDENCIES test_stages action_flow_test_models)
  add_rostest(test/ros/classifier_bad_model.test ARGS ${ACTION_FLOW_MODEL_ARGS} DEPENDENCIES test_stages action_flow_test_models)
  add_rostest(test/ros/lazy.test ARGS ${ACTION_FLOW_MODEL_ARGS} DEPENDENCIES test_stages action_flow_test_models)
  add_rostest(test/ros/zero_copy.test ARGS ${ACTION_FLOW_MODEL_ARGS} DEPENDENCIES test_stages action_flow_test_models)
  add_rostest(test/ros/diagnostics.test DEPENDENCIES test_stages)
  add_rostest(test/ros/markers.test ARGS ${ACTION_FLOW_MODEL_ARGS} DEPENDENCIES test_stages action_flow_test_models)
  add_rostest(test/ros/zero_copy_detects_copy.test ARGS ${ACTION_FLOW_MODEL_ARGS} DEPENDENCIES test_stages action_flow_test_models)
  add_rostest(test/ros/real_data.test ARGS data:=${PROJECT_SOURCE_DIR}/../shared/data DEPENDENCIES test_real_data)
  add_rostest(test/ros/driver_dummy.test DEPENDENCIES test_stages)
  add_rostest(test/ros/driver_absent.test DEPENDENCIES test_stages)
  add_rostest(test/ros/annotator.test DEPENDENCIES test_annotator)
  add_rostest(test/ros/annotator_scene.test DEPENDENCIES test_annotator)
  # A fakenect dump written by synth (p04 waving, 60 frames, about 90 MB) for kinect.launch backend:=freenect.
  set(ACTION_FLOW_TEST_DUMP ${CMAKE_BINARY_DIR}/test_fakenect/ias/p04_wave_1.fakenect)
  add_custom_command(OUTPUT ${ACTION_FLOW_TEST_DUMP}/INDEX.txt
    COMMAND synth --out ${CMAKE_BINARY_DIR}/test_fakenect --person p04 --action wave --repetition 1 --frames 60 --fakenect --quiet
    DEPENDS synth
    COMMENT "Writing the fakenect test dump")
  add_custom_target(action_flow_test_dump DEPENDS ${ACTION_FLOW_TEST_DUMP}/INDEX.txt)
  add_dependencies(tests action_flow_test_dump)
  add_rostest(test/ros/kinect_fakenect.test
    ARGS model:=${ACTION_FLOW_TEST_MODELS}/posture_flow.afm corrupt_model:=${ACTION_FLOW_TEST_MODELS}/corrupt.afm dump:=${ACTION_FLOW_TEST_DUMP}
    DEPENDENCIES test_stages action_flow_test_models action_flow_test_dump)
endif()
