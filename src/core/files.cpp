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
std::string trimmed(const std::string& s)
{
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos)
    return "";
  return s.substr(b, s.find_last_not_of(" \t\r\n") - b + 1);
}

void writeTextAtomically(const std::string& path, const std::string& text)
{
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    f.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!f.flush())
    {
      std::remove(tmp.c_str());
      throw std::runtime_error(path + ": cannot write (missing folder, no permission or disk full?)");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0)
  {
    std::remove(tmp.c_str());
    throw std::runtime_error(path + ": cannot rename the temporary file into place");
  }
}

}  // namespace action_flow
