// Conversions of the stage types to and from their wire messages. roscpp calls these only for
// subscribers in another process; in-process subscribers get the objects themselves.
#include <action_flow/ros/stage_types.h>

namespace action_flow
{
namespace
{
geometry_msgs::Point toPoint(const Eigen::Vector3f& v)
{
  geometry_msgs::Point p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}
geometry_msgs::Vector3 toVector(const Eigen::Vector3f& v)
{
  geometry_msgs::Vector3 p;
  p.x = v.x();
  p.y = v.y();
  p.z = v.z();
  return p;
}
template <class P>
Eigen::Vector3f toEigen(const P& p)
{
  return Eigen::Vector3f(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
}
}  // namespace

PersonState toMessage(const PersonInfo& in)
{
  PersonState out;
  out.id = in.id;
  out.position = toPoint(in.position);
  out.velocity = toVector(in.velocity);
  out.height = in.height;
  return out;
}

PersonGrid toMessage(const PersonFrame& in)
{
  PersonGrid out;
  out.origin = toPoint(in.origin);
  out.x_axis = toVector(in.axes.col(0));
  out.y_axis = toVector(in.axes.col(1));
  out.z_axis = toVector(in.axes.col(2));
  out.height = in.height;
  return out;
}

void fromMessage(const PersonState& person, const PersonGrid& grid, PersonInfo& out)
{
  out.id = person.id;
  out.position = toEigen(person.position);
  out.velocity = toEigen(person.velocity);
  out.height = person.height;
  out.frame.origin = toEigen(grid.origin);
  out.frame.axes.col(0) = toEigen(grid.x_axis);
  out.frame.axes.col(1) = toEigen(grid.y_axis);
  out.frame.axes.col(2) = toEigen(grid.z_axis);
  out.frame.height = grid.height;
}

PersonCloudArray toMessage(const PeopleClouds& in)
{
  PersonCloudArray out;
  out.header = in.header;
  out.lost = in.lost;
  out.reset = in.reset;
  for (const auto& p : in.people)
  {
    PersonCloud c;
    c.person = toMessage(p.info);
    c.grid = toMessage(p.info.frame);
    if (p.cloud)
      pcl::toROSMsg(*p.cloud, c.cloud);
    c.cloud.header = in.header;
    out.people.push_back(std::move(c));
  }
  return out;
}

void fromMessage(const PersonCloudArray& in, PeopleClouds& out)
{
  out = PeopleClouds();
  out.header = in.header;
  out.lost = in.lost;
  out.reset = in.reset;
  for (const auto& c : in.people)
  {
    PeopleClouds::Person p;
    fromMessage(c.person, c.grid, p.info);
    auto cloud = boost::make_shared<Cloud>();
    if (!c.cloud.data.empty())
      pcl::fromROSMsg(c.cloud, *cloud);
    p.cloud = cloud;
    out.people.push_back(std::move(p));
  }
}

PersonFlowArray toMessage(const PeopleFlow& in)
{
  PersonFlowArray out;
  out.header = in.header;
  out.lost = in.lost;
  out.reset = in.reset;
  for (const auto& p : in.people)
  {
    PersonFlow f;
    f.person = toMessage(p.info);
    f.grid = toMessage(p.info.frame);
    f.status = p.status;
    f.dt = p.dt;
    if (p.flow)
    {
      f.vectors.reserve(6 * p.flow->size());
      for (const auto& v : *p.flow)
      {
        f.vectors.insert(f.vectors.end(), v.position.data(), v.position.data() + 3);
        f.vectors.insert(f.vectors.end(), v.velocity.data(), v.velocity.data() + 3);
      }
    }
    if (p.cloud)
    {
      pcl::toROSMsg(*p.cloud, f.cloud);
      f.cloud.header = in.header;
    }
    out.people.push_back(std::move(f));
  }
  return out;
}

void fromMessage(const PersonFlowArray& in, PeopleFlow& out)
{
  out = PeopleFlow();
  out.header = in.header;
  out.lost = in.lost;
  out.reset = in.reset;
  for (const auto& f : in.people)
  {
    PeopleFlow::Person p;
    fromMessage(f.person, f.grid, p.info);
    p.status = f.status;
    p.dt = f.dt;
    auto flow = boost::make_shared<FlowVectors>();
    for (std::size_t i = 0; i + 6 <= f.vectors.size(); i += 6)
      flow->push_back({ Eigen::Vector3f(f.vectors[i], f.vectors[i + 1], f.vectors[i + 2]),
                        Eigen::Vector3f(f.vectors[i + 3], f.vectors[i + 4], f.vectors[i + 5]) });
    p.flow = flow;
    if (!f.cloud.data.empty())
    {
      auto cloud = boost::make_shared<Cloud>();
      pcl::fromROSMsg(f.cloud, *cloud);
      p.cloud = cloud;
    }
    out.people.push_back(std::move(p));
  }
}

}  // namespace action_flow
