# ROS wrappers: the pipeline's nodelets, their test aids, launch checks and rostests.
find_package(PkgConfig REQUIRED)
pkg_check_modules(OPENNI2 REQUIRED libopenni2)

# Stage types (zero-copy message traits) and parameter reading, shared by every nodelet.
add_library(action_flow_ros src/nodelets/stage_types.cpp src/nodelets/params.cpp)
add_dependencies(action_flow_ros ${PROJECT_NAME}_generate_messages_cpp)
target_link_libraries(action_flow_ros action_flow_core ${catkin_LIBRARIES})

# Flow, descriptor and classifier stages.
add_library(action_flow_nodelets
  src/nodelets/flow_nodelet.cpp
  src/nodelets/descriptor_nodelet.cpp
  src/nodelets/classifier_nodelet.cpp)
target_link_libraries(action_flow_nodelets action_flow_ros)

# OpenNI2 driver.
add_library(action_flow_driver src/driver/openni2_device.cpp src/nodelets/driver_nodelet.cpp)
target_include_directories(action_flow_driver SYSTEM PRIVATE ${OPENNI2_INCLUDE_DIRS})
target_link_libraries(action_flow_driver ${OPENNI2_LIBRARIES} ${catkin_LIBRARIES})

# People tracker stage, over the tracker part's core library.
add_library(action_flow_tracker_nodelet src/nodelets/people_tracker_nodelet.cpp)
target_link_libraries(action_flow_tracker_nodelet action_flow_ros ${catkin_LIBRARIES})
if(TARGET action_flow_tracker)
  target_link_libraries(action_flow_tracker_nodelet action_flow_tracker)
endif()

# Test aids (exported too so that rostests can load them by name): a scene / person-cloud
# publisher and the zero-copy probe.
add_library(action_flow_test_nodelets test/ros/test_scene.cpp test/ros/test_scene_publisher.cpp test/ros/zero_copy_probe.cpp)
target_link_libraries(action_flow_test_nodelets action_flow_ros ${catkin_LIBRARIES})

install(TARGETS action_flow_ros action_flow_nodelets action_flow_driver action_flow_tracker_nodelet
        action_flow_test_nodelets
  ARCHIVE DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  LIBRARY DESTINATION ${CATKIN_PACKAGE_LIB_DESTINATION}
  RUNTIME DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
install(FILES nodelets.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
install(DIRECTORY launch config DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
