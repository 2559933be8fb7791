#pragma once
// A tiny fork-join helper for the CPU algorithms of geometry/: split [0, count) into fixed chunks
// and run them on a few std::threads. Chunk boundaries depend only on `count` and `grain`, never on
// the thread count, so code that reduces per chunk and then combines the chunks in order gets
// bit-identical results however many threads ran.

#include <cstddef>
#include <functional>

namespace gimg::geo {

// Threads used when a call does not say: std::thread::hardware_concurrency() (at least 1), or the
// value set here (0 restores the default). Tests use it to check thread-count independence.
void set_default_thread_count(unsigned threads);
unsigned default_thread_count();

// Calls body(chunk_index, begin, end) for every chunk [begin, end) of [0, count), chunks of `grain`
// items (the last one shorter), each exactly once, from up to `threads` threads (0 = default).
// The chunk count is ceil(count / grain). The first exception thrown by a body is rethrown here
// after all threads have stopped.
void parallel_for_chunks(std::size_t count, std::size_t grain,
                         const std::function<void(std::size_t chunk, std::size_t begin, std::size_t end)>& body,
                         unsigned threads = 0);

inline std::size_t chunk_count(std::size_t count, std::size_t grain) {
    return grain == 0 ? 0 : (count + grain - 1) / grain;
}

}  // namespace gimg::geo
