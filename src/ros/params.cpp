#include <action_flow/ros/params.h>

#include <cstdio>
#include <stdexcept>
#include <string>

namespace action_flow
{
namespace
{
// A ROS parameter's value in param_table.h's text form.
std::string xmlRpcText(XmlRpc::XmlRpcValue& v, const std::string& name)
{
  switch (v.getType())
  {
    case XmlRpc::XmlRpcValue::TypeBoolean:
      return paramText(static_cast<bool>(v));
    case XmlRpc::XmlRpcValue::TypeInt:
      return paramText(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble:
      return paramText(static_cast<double>(v));
    case XmlRpc::XmlRpcValue::TypeString:
      return static_cast<std::string>(v);
    case XmlRpc::XmlRpcValue::TypeArray:
    {
      std::string out = "[";
      for (int i = 0; i < v.size(); ++i)
        out += (i ? ", " : "") + xmlRpcText(v[i], name);
      return out + "]";
    }
    default:
      throw std::invalid_argument(name + ": not a number, boolean, string or list");
  }
}

// Every parameter of P that is set in nh's namespace, over P's defaults in p.
template <class P>
P readParams(const ros::NodeHandle& nh, P p)
{
  for (const ParamEntry& e : paramEntries(p))
  {
    XmlRpc::XmlRpcValue value;
    if (nh.getParam(e.name, value))
      setParam(p, e.name, xmlRpcText(value, e.name));
  }
  return p;
}
}  // namespace

RecognitionParams readRecognitionParams(const ros::NodeHandle& nh)
{
  return readParams(nh, defaultRecognitionParams());
}

PolicyParams readPolicyParams(const ros::NodeHandle& nh)
{
  PolicyParams p = readParams(nh, PolicyParams());
  p.validate();
  return p;
}

TrackerParams readTrackerParams(const ros::NodeHandle& nh)
{
  return readParams(nh, TrackerParams());
}

}  // namespace action_flow
