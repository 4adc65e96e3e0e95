/**
 * @file files.h
 * @brief What the tools and stages check before opening a file that they read whole, and how
 *        they write one.
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

/**
 * @brief Writes @p text (any bytes) to @p path whole or not at all: to "<path>.tmp", then renamed
 *        into place, so an interrupted run never leaves a half-written file. Every file the
 *        package writes whole goes through it (models, caches, reports, indexes, benchmarks).
 * @throws std::runtime_error naming the file if it cannot be written or renamed
 */
void writeTextAtomically(const std::string& path, const std::string& text);

/** @brief @p s without leading and trailing spaces, tabs, carriage returns and newlines. */
std::string trimmed(const std::string& s);
}  // namespace action_flow
