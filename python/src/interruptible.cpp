#include "interruptible.h"

#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <thread>

namespace volguide::python {

namespace py = pybind11;

namespace {
// How often the waiting thread looks at Python's pending signals: Ctrl-C feels immediate, and the
// GIL is taken ~20 times a second only.
constexpr auto kSignalPollInterval = std::chrono::milliseconds(50);

// The pending Python exception, taken out of the interpreter so that the GIL may be released
// while the job winds down; restore() puts it back (the GIL must be held for both).
class PendingError {
  public:
    void fetch() { PyErr_Fetch(&type_, &value_, &trace_); }
    bool empty() const { return type_ == nullptr; }
    [[noreturn]] void raise() {
        PyErr_Restore(type_, value_, trace_);
        type_ = value_ = trace_ = nullptr;
        throw py::error_already_set();
    }
    ~PendingError() {
        Py_XDECREF(type_);
        Py_XDECREF(value_);
        Py_XDECREF(trace_);
    }

  private:
    PyObject *type_ = nullptr, *value_ = nullptr, *trace_ = nullptr;
};
}  // namespace

void run_interruptible(const std::function<void()>& job, std::atomic<bool>& cancel) {
    std::mutex mutex;
    std::condition_variable finished_cv;
    bool finished = false;
    std::exception_ptr failure;
    std::thread worker([&] {
        try {
            job();
        } catch (...) {
            failure = std::current_exception();
        }
        std::lock_guard lock(mutex);
        finished = true;
        finished_cv.notify_all();
    });
    PendingError interrupt;
    while (true) {
        {
            py::gil_scoped_release release;
            std::unique_lock lock(mutex);
            if (finished_cv.wait_for(lock, kSignalPollInterval, [&] { return finished; })) break;
        }
        if (interrupt.empty() && PyErr_CheckSignals() != 0) {
            interrupt.fetch();
            cancel.store(true);
        }
    }
    {
        py::gil_scoped_release release;
        worker.join();
    }
    if (!interrupt.empty()) interrupt.raise();
    if (failure) std::rethrow_exception(failure);
}

}  // namespace volguide::python
