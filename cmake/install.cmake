# The install space beyond the targets (each part's file installs its own libraries and tools):
# the user scripts, the nodelets' plugin description without the test aids, the license; and the
# tests of the install space and of catkin_lint (test/install/).

# User scripts, run with rosrun action_flow <script>; their #! line is the system's /usr/bin/python3.
# Installed with install(PROGRAMS), not catkin_install_python: that also puts a relay of each in the
# devel space, which sits inside the package (devel/), so rosrun would find every script twice there
# (the relay and the source) and refuse it as non-unique. The source-tree scripts (scripts/setup, test, demo, fuzz,
# run_experiments, bench_pipeline) build and run the checkout and stay out of the install space.
set(ACTION_FLOW_USER_SCRIPTS
  scripts/label_bag.py
  scripts/stream_labels.py
  scripts/plot_report.py
  scripts/plot_timeline.py
  scripts/plot_tracks.py
  scripts/plot_detection.py
  scripts/bench_pipeline_report.py
  scripts/results_table.py
  scripts/validate_report.py)
install(PROGRAMS ${ACTION_FLOW_USER_SCRIPTS} DESTINATION ${CATKIN_PACKAGE_BIN_DESTINATION})
# evaluate draws its report with <package path>/scripts/plot_report.py (and plot_timeline.py for the
# online protocol, plot_tracks.py for evaluate_tracking, plot_detection.py for the detection protocol): a copy there,
# not executable, so that rosrun finds one executable of each name.
install(FILES scripts/plot_report.py scripts/plot_timeline.py scripts/plot_tracks.py scripts/plot_detection.py DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION}/scripts)

# The installed nodelets.xml: the source file without the test aids' library (its classes are for
# the rostests, which run in the devel space; the library is not installed).
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/nodelets.xml)
file(READ ${PROJECT_SOURCE_DIR}/nodelets.xml _action_flow_nodelets_xml)
string(REGEX REPLACE "<library path=\"lib/libaction_flow_test_nodelets\">.*</library>[ \t\r\n]*" ""
       _action_flow_nodelets_xml "${_action_flow_nodelets_xml}")
if(_action_flow_nodelets_xml MATCHES "test_nodelets|Test aid")
  message(FATAL_ERROR "nodelets.xml: the test aids' <library> must be the last one (cmake/install.cmake leaves it out of the install space)")
endif()
file(WRITE ${CMAKE_CURRENT_BINARY_DIR}/installspace/nodelets.xml "${_action_flow_nodelets_xml}")
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/installspace/nodelets.xml DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})

install(FILES LICENSE DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})

if(CATKIN_ENABLE_TESTING)
  # The install space, installed into a temporary prefix and used with nothing but its own setup
  # file (about 30 s): the tools start, every nodelet of the launch files loads into a manager, the
  # messages import in Python, the missing default model is reported, and no test aid is installed.
  # It installs what the build made: run it after the whole build (scripts/test does).
  # (catkin's run_tests.py runs each COMMAND word as a shell command of its own: one string.)
  catkin_run_tests_target(install install_space test_install_space.xml
    COMMAND "'${PROJECT_SOURCE_DIR}/test/install/test_install_space.sh' '${CMAKE_BINARY_DIR}' '${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/test_install_space.xml'"
    WORKING_DIRECTORY ${CMAKE_BINARY_DIR})
  # rosrun finds the tools in the devel space (about 2 s).
  catkin_run_tests_target(devel rosrun test_devel_rosrun.xml
    COMMAND "'${PROJECT_SOURCE_DIR}/test/install/test_devel_rosrun.sh' '${CATKIN_DEVEL_PREFIX}' '${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/test_devel_rosrun.xml'"
    WORKING_DIRECTORY ${CMAKE_BINARY_DIR})
  # catkin_lint -W2 --strict on the package (about 1 s).
  catkin_run_tests_target(lint catkin_lint test_catkin_lint.xml
    COMMAND "'${PROJECT_SOURCE_DIR}/test/install/test_catkin_lint.sh' '${PROJECT_SOURCE_DIR}' '${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/test_catkin_lint.xml'"
    WORKING_DIRECTORY ${PROJECT_SOURCE_DIR})
endif()
