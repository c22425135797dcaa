// Whole-buffer reads and writes on a pipe or a socket, for the child processes that talk
// to Mesa (bench/mesa_peer.cpp, conformance/mesa_player.cpp): llvmpipe fixes its thread
// count per process, so each peer runs in a forked child.
#pragma once

#include <cstddef>

namespace rg::io {

// Writes all `size` bytes; false when the peer is gone or the descriptor fails. On a
// socket the write never raises SIGPIPE (MSG_NOSIGNAL): a dead peer is an error, not a
// signal.
bool writeAll(int fd, const void* data, size_t size);
// Reads exactly `size` bytes; false at end of file or on an error.
bool readAll(int fd, void* data, size_t size);

}  // namespace rg::io
