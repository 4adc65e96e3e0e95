#include <action_flow/files.h>

#include <sys/stat.h>

namespace action_flow
{
std::string whyNotARegularFile(const std::string& path)
{
  struct stat st;
  if (::stat(path.c_str(), &st) != 0)
    return "does not exist";
  if (S_ISDIR(st.st_mode))
    return "is a directory";
  if (!S_ISREG(st.st_mode))
    return "is not a regular file (a FIFO, socket or device)";
  return "";
}
}  // namespace action_flow
