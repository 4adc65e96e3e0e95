#include <action_flow/files.h>

#include <cstdio>
#include <fstream>
#include <stdexcept>

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
void writeTextAtomically(const std::string& path, const std::string& text)
{
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::trunc);
    f << text;
    if (!f.flush())
      throw std::runtime_error(path + ": cannot write");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
    throw std::runtime_error(path + ": cannot rename the temporary file into place");
}

}  // namespace action_flow
