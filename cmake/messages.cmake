# Messages and services of the pipeline (included before catkin_package, as catkin requires).
add_message_files(DIRECTORY msg FILES
  ActionLabel.msg
  PersonState.msg
  TrackedPeople.msg
  PersonGrid.msg
  PersonCloud.msg
  PersonCloudArray.msg
  PersonFlow.msg
  PersonFlowArray.msg
  FrameDescriptor.msg
  FrameDescriptorArray.msg
  ActionState.msg
  ActionStateArray.msg
)
add_service_files(DIRECTORY srv FILES Classify.srv)
generate_messages(DEPENDENCIES std_msgs geometry_msgs sensor_msgs)
