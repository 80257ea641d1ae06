// bench/peers/task_pool.cpp: the thread pool of task_pool.h.
#include "task_pool.h"

namespace rubble::peers {

struct TaskPool::Task {
    Function function;
    void* context;
    bool done = false; ///< guarded by the pool's mutex
};

TaskPool::TaskPool(int threads) {
    for (int i = 0; i < threads; ++i) threads_.emplace_back([this] { work(); });
}

TaskPool::~TaskPool() {
    {
        std::lock_guard<std::mutex> lock(mutex_);
        stop_ = true;
    }
    queued_.notify_all();
    for (std::thread& t : threads_) t.join();
}

TaskPool::Task* TaskPool::enqueue(Function function, void* context) {
    Task* task = new Task{function, context};
    {
        std::lock_guard<std::mutex> lock(mutex_);
        queue_.push_back(task);
    }
    queued_.notify_one();
    // A thread waiting in finish (a task waiting on its own sub-task) may take it too.
    done_.notify_all();
    return task;
}

void TaskPool::runFront(std::unique_lock<std::mutex>& lock) {
    Task* task = queue_.front();
    queue_.pop_front();
    lock.unlock();
    task->function(task->context);
    lock.lock();
    task->done = true;
    done_.notify_all();
}

void TaskPool::finish(Task* task) {
    std::unique_lock<std::mutex> lock(mutex_);
    while (!task->done) {
        if (!queue_.empty()) runFront(lock);
        else done_.wait(lock);
    }
    lock.unlock();
    delete task;
}

void TaskPool::work() {
    std::unique_lock<std::mutex> lock(mutex_);
    for (;;) {
        queued_.wait(lock, [this] { return stop_ || !queue_.empty(); });
        if (queue_.empty()) return; // stopping, nothing left
        runFront(lock);
    }
}

} // namespace rubble::peers
