// bench/peers/task_pool.h: a small thread pool for a peer engine's task callbacks (Box3D's
// enqueue/finish pair): tasks run once each, on a pool thread or on a thread waiting for one.
#pragma once

#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>
#include <vector>

namespace rubble::peers {

/// Runs queued tasks on `threads` threads. A thread that waits for a task (finish) runs queued
/// tasks meanwhile, so a step that enqueues as many tasks as it has workers and then waits on
/// each makes progress with threads + 1 threads, the caller being the last.
class TaskPool {
  public:
    using Function = void (*)(void* context);
    struct Task; ///< one enqueued call, owned by the pool until finish returns

    explicit TaskPool(int threads);
    ~TaskPool();
    TaskPool(const TaskPool&) = delete;
    TaskPool& operator=(const TaskPool&) = delete;

    /// Queues `function(context)`; the handle goes to finish, once.
    Task* enqueue(Function function, void* context);
    /// Returns once the task has run (running queued tasks on this thread while it waits) and
    /// frees it.
    void finish(Task* task);
    /// Pool threads (the caller of finish comes on top).
    int threads() const { return int(threads_.size()); }

  private:
    void work();
    // Runs the front task with the lock released; the lock is held again on return.
    void runFront(std::unique_lock<std::mutex>& lock);

    std::mutex mutex_;
    std::condition_variable queued_; ///< a task was queued, or the pool stops
    std::condition_variable done_;   ///< a task finished, or one was queued
    std::deque<Task*> queue_;
    bool stop_ = false;
    std::vector<std::thread> threads_;
};

} // namespace rubble::peers
