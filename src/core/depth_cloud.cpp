#include <action_flow/depth_cloud.h>

#include <cmath>
#include <limits>

namespace action_flow
{
void depthToCloud(const float* depth_m, const std::uint8_t* rgb, int width, int height, const Intrinsics& k,
                  Cloud& out)
{
  out.width = static_cast<std::uint32_t>(width);
  out.height = static_cast<std::uint32_t>(height);
  out.is_dense = false;
  out.points.resize(static_cast<std::size_t>(width) * height);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int v = 0; v < height; ++v)
    for (int u = 0; u < width; ++u)
    {
      const std::size_t i = static_cast<std::size_t>(v) * width + u;
      PointT& p = out.points[i];
      const float z = depth_m[i];
      if (std::isfinite(z) && z > 0.0f)
      {
        p.x = static_cast<float>((u - k.cx) * z / k.fx);
        p.y = static_cast<float>((v - k.cy) * z / k.fy);
        p.z = z;
      }
      else
      {
        p.x = p.y = p.z = nan;
      }
      p.r = rgb[3 * i];
      p.g = rgb[3 * i + 1];
      p.b = rgb[3 * i + 2];
    }
}

}  // namespace action_flow
