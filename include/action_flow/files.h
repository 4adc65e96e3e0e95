/**
 * @file files.h
 * @brief What the tools and stages check before opening a file that they read whole.
 */
#pragma once

#include <string>

namespace action_flow
{
/**
 * @brief "" when @p path is a regular file, else why not: "does not exist", "is a directory" or
 *        "is not a regular file (a FIFO, socket or device)". Opening a FIFO would block the
 *        reader (and, for a model, the whole nodelet manager's load service) until someone writes.
 */
std::string whyNotARegularFile(const std::string& path);
}  // namespace action_flow
