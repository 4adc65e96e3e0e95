/**
 * @file stage_types.h
 * @brief The C++ types that travel between the nodelets of the pipeline, with ROS message traits
 *        and serialization (as pcl_ros does for pcl::PointCloud).
 *
 * Inside one nodelet manager roscpp hands a subscriber the very boost::shared_ptr<const T> that
 * the previous stage published: no copy, no serialization. Only when a subscriber sits in another
 * process does roscpp serialize, and then these types go on the wire as the generated messages
 * named in their traits (PersonCloudArray, PersonFlowArray, FrameDescriptorArray,
 * ActionStateArray), so `rostopic echo` and remote nodes read them like any message.
 *
 * Every type holds `source`: the object it was computed from. It is never serialized (a remote
 * reader gets an empty pointer); in-process it keeps the chain inspectable (the classifier draws
 * flow arrows from its input's source) and lets a probe prove that no stage copied its input.
 */
#pragma once

#include <action_flow/ActionStateArray.h>
#include <action_flow/FrameDescriptorArray.h>
#include <action_flow/PersonCloudArray.h>
#include <action_flow/PersonFlowArray.h>
#include <action_flow/grid_descriptor.h>
#include <action_flow/types.h>

#include <boost/shared_ptr.hpp>
#include <pcl_conversions/pcl_conversions.h>
#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <std_msgs/Header.h>

#include <cstdint>
#include <vector>

namespace action_flow
{
/** @brief A tracked person's state in one frame, as the stages after the tracker need it. */
struct PersonInfo
{
  std::uint32_t id = 0;
  Eigen::Vector3f position = Eigen::Vector3f::Zero();  ///< centroid
  Eigen::Vector3f velocity = Eigen::Vector3f::Zero();  ///< motion model (m/s)
  float height = 0.0f;                                 ///< top of head above the ground (m)
  PersonFrame frame;                                   ///< where the descriptor grid sits

  /** @brief The top of the head (for labels drawn above it). */
  Eigen::Vector3f head() const { return frame.origin + frame.axes.col(1) * height; }
};

/** @brief The people tracker's output for one input frame: each tracked person's cloud. */
struct PeopleClouds
{
  struct Person
  {
    PersonInfo info;
    boost::shared_ptr<const Cloud> cloud;  ///< at the tracker's person voxel size; never modified
  };
  std_msgs::Header header;
  std::vector<Person> people;
  std::vector<std::uint32_t> lost;  ///< tracks that ended at this frame
  bool reset = false;               ///< time went backwards: downstream state must be dropped
  boost::shared_ptr<const Cloud> source;  ///< the input cloud (in-process only)

  using Ptr = boost::shared_ptr<PeopleClouds>;
  using ConstPtr = boost::shared_ptr<const PeopleClouds>;
};

/** @brief The flow stage's output for one input frame: each tracked person's 3D flow. */
struct PeopleFlow
{
  /** Values of `status`, as in PersonFlow.msg. */
  enum : std::uint8_t
  {
    kFirst = PersonFlow::FIRST,
    kFlow = PersonFlow::FLOW,
    kReset = PersonFlow::RESET
  };
  struct Person
  {
    PersonInfo info;
    std::uint8_t status = kFirst;
    double dt = 0.0;
    boost::shared_ptr<const FlowVectors> flow;  ///< empty unless status is kFlow
    boost::shared_ptr<const Cloud> cloud;       ///< the person's cloud of this frame (the tracker's, not copied)
  };
  std_msgs::Header header;
  std::vector<Person> people;
  std::vector<std::uint32_t> lost;
  bool reset = false;
  boost::shared_ptr<const PeopleClouds> source;  ///< the person clouds (in-process only)

  using Ptr = boost::shared_ptr<PeopleFlow>;
  using ConstPtr = boost::shared_ptr<const PeopleFlow>;
};

/** @brief A generated message plus the object it was computed from (not serialized). */
template <class Msg, class Source>
struct WithSource : public Msg
{
  boost::shared_ptr<const Source> source;

  using Ptr = boost::shared_ptr<WithSource>;
  using ConstPtr = boost::shared_ptr<const WithSource>;
};

/** @brief The descriptor stage's output: one frame descriptor per tracked person. */
using FrameDescriptors = WithSource<FrameDescriptorArray, PeopleFlow>;
/** @brief The classifier's per-frame state of every track it saw in this frame. */
using ActionStates = WithSource<ActionStateArray, FrameDescriptors>;

/** @name Conversions to and from the wire messages (used only when serializing). */
///@{
PersonCloudArray toMessage(const PeopleClouds& in);
void fromMessage(const PersonCloudArray& in, PeopleClouds& out);
PersonFlowArray toMessage(const PeopleFlow& in);
void fromMessage(const PersonFlowArray& in, PeopleFlow& out);
PersonState toMessage(const PersonInfo& in);
PersonGrid toMessage(const PersonFrame& in);
void fromMessage(const PersonState& person, const PersonGrid& grid, PersonInfo& out);
///@}

}  // namespace action_flow

namespace ros
{
namespace message_traits
{
/** Traits of a C++ stage type T that goes on the wire as the generated message W. */
#define ACTION_FLOW_WIRE_TRAITS(T, W)                                                        \
  template <>                                                                                \
  struct MD5Sum<T>                                                                           \
  {                                                                                          \
    static const char* value() { return MD5Sum<W>::value(); }                                \
    static const char* value(const T&) { return value(); }                                   \
  };                                                                                         \
  template <>                                                                                \
  struct DataType<T>                                                                         \
  {                                                                                          \
    static const char* value() { return DataType<W>::value(); }                              \
    static const char* value(const T&) { return value(); }                                   \
  };                                                                                         \
  template <>                                                                                \
  struct Definition<T>                                                                       \
  {                                                                                          \
    static const char* value() { return Definition<W>::value(); }                            \
    static const char* value(const T&) { return value(); }                                   \
  };                                                                                         \
  template <>                                                                                \
  struct HasHeader<T> : TrueType                                                             \
  {                                                                                          \
  };

ACTION_FLOW_WIRE_TRAITS(action_flow::PeopleClouds, action_flow::PersonCloudArray)
ACTION_FLOW_WIRE_TRAITS(action_flow::PeopleFlow, action_flow::PersonFlowArray)
#undef ACTION_FLOW_WIRE_TRAITS

template <class M, class S>
struct MD5Sum<action_flow::WithSource<M, S>> : MD5Sum<M>
{
};
template <class M, class S>
struct DataType<action_flow::WithSource<M, S>> : DataType<M>
{
};
template <class M, class S>
struct Definition<action_flow::WithSource<M, S>> : Definition<M>
{
};
template <class M, class S>
struct HasHeader<action_flow::WithSource<M, S>> : HasHeader<M>
{
};
}  // namespace message_traits

namespace serialization
{
/** Serializes a stage type T through its wire message W (a conversion, only for remote subscribers). */
#define ACTION_FLOW_WIRE_SERIALIZER(T, W)                                                    \
  template <>                                                                                \
  struct Serializer<T>                                                                       \
  {                                                                                          \
    template <typename Stream>                                                               \
    inline static void write(Stream& stream, const T& m)                                     \
    {                                                                                        \
      stream.next(action_flow::toMessage(m));                                                \
    }                                                                                        \
    template <typename Stream>                                                               \
    inline static void read(Stream& stream, T& m)                                            \
    {                                                                                        \
      W wire;                                                                                \
      stream.next(wire);                                                                     \
      action_flow::fromMessage(wire, m);                                                     \
    }                                                                                        \
    inline static uint32_t serializedLength(const T& m)                                      \
    {                                                                                        \
      return serializationLength(action_flow::toMessage(m));                                 \
    }                                                                                        \
  };

ACTION_FLOW_WIRE_SERIALIZER(action_flow::PeopleClouds, action_flow::PersonCloudArray)
ACTION_FLOW_WIRE_SERIALIZER(action_flow::PeopleFlow, action_flow::PersonFlowArray)
#undef ACTION_FLOW_WIRE_SERIALIZER

template <class M, class S>
struct Serializer<action_flow::WithSource<M, S>>
{
  template <typename Stream>
  inline static void write(Stream& stream, const action_flow::WithSource<M, S>& m)
  {
    Serializer<M>::write(stream, static_cast<const M&>(m));
  }
  template <typename Stream>
  inline static void read(Stream& stream, action_flow::WithSource<M, S>& m)
  {
    Serializer<M>::read(stream, static_cast<M&>(m));
  }
  inline static uint32_t serializedLength(const action_flow::WithSource<M, S>& m)
  {
    return Serializer<M>::serializedLength(static_cast<const M&>(m));
  }
};
}  // namespace serialization
}  // namespace ros
