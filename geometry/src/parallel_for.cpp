#include "gimg/geometry/parallel_for.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace gimg::geo {

namespace {
std::atomic<unsigned> g_thread_override{0};
}

void set_default_thread_count(unsigned threads) { g_thread_override.store(threads); }

unsigned default_thread_count() {
    if (unsigned n = g_thread_override.load(); n > 0) return n;
    return std::max(1u, std::thread::hardware_concurrency());
}

void parallel_for_chunks(std::size_t count, std::size_t grain,
                         const std::function<void(std::size_t, std::size_t, std::size_t)>& body, unsigned threads) {
    if (count == 0) return;
    grain = std::max<std::size_t>(grain, 1);
    const std::size_t chunks = chunk_count(count, grain);
    if (threads == 0) threads = default_thread_count();
    const std::size_t workers = std::min<std::size_t>(threads, chunks);

    // Chunks are handed out dynamically (an atomic counter) so uneven chunks balance themselves;
    // which thread runs a chunk never changes what the chunk computes.
    std::atomic<std::size_t> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    auto work = [&] {
        for (;;) {
            const std::size_t c = next.fetch_add(1);
            if (c >= chunks) return;
            try {
                const std::size_t begin = c * grain;
                body(c, begin, std::min(count, begin + grain));
            } catch (...) {
                std::lock_guard lock(error_mutex);
                if (!error) error = std::current_exception();
                next.store(chunks);  // stop handing out work
                return;
            }
        }
    };
    if (workers <= 1) {
        work();
    } else {
        std::vector<std::thread> pool;
        pool.reserve(workers - 1);
        for (std::size_t i = 1; i < workers; ++i) pool.emplace_back(work);
        work();
        for (auto& t : pool) t.join();
    }
    if (error) std::rethrow_exception(error);
}

}  // namespace gimg::geo
