#pragma once
// What every generated robot's Python module shares (mbgen generate --python writes
// <robot>_python.cpp, a pybind11 module that binds each generated function with this): reading
// NumPy arrays of the shapes the generated header states, with or without a leading batch
// dimension, making the outputs, and calling the function once per state with the GIL released.
// Only pybind11 and NumPy: the generated module includes nothing else of the runtime.
//
// Shapes. An input of shape S is given either with exactly that shape (one state) or with shape
// (N,) + S (N states; every batched input of a call must have the same N, and an input given
// with shape S alone is used for every state). The outputs have shape S, or (N,) + S when any
// input was batched. A vector's shape is (n,); matrices are (rows, cols), row-major as the
// generated code writes them. Anything else is a ValueError naming the function, the argument,
// the shape expected and the shape given.
//
// Copies. An input that is already a C-contiguous float64 array is read in place; anything else
// that NumPy can convert (a list, float32, a strided view) is converted once per call.
//
// Batch functions. A robot generated with --batch W has <function>_batch over W states in
// structure-of-arrays layout (x[i][w]: entry i of state w); a batched call then runs W states at
// a time through it (run_lanes: each group's inputs gathered into that layout, its outputs
// scattered back) and the last N mod W states through the one-state function. Both compute the
// same operations in the same order (docs/generator.md, "Many states per call"), so a batch equals
// one call per state bit for bit either way.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace mbgen::python {

namespace py = pybind11;

/// A float64, C-contiguous array: pybind11 converts to it only when it must.
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// "(47,)" or "(N, 3, 4)": a shape as NumPy prints it.
inline std::string shape_text(const std::vector<py::ssize_t>& shape, bool batched = false) {
  std::string out = "(";
  if (batched) out += shape.empty() ? "N," : "N, ";
  for (std::size_t i = 0; i < shape.size(); ++i) out += (i ? ", " : "") + std::to_string(shape[i]);
  if (!batched && shape.size() == 1) out += ',';
  return out + ")";
}

/// One call of a generated function. Declare the inputs, then the outputs, then run().
class Call {
 public:
  explicit Call(std::string function) : function_(std::move(function)) {}

  /// The input `name` of shape `shape` from `object`; returns its index for State::in.
  int input(const char* name, const py::handle& object, std::vector<py::ssize_t> shape) {
    Array a = convert(name, object);
    const std::size_t rank = shape.size();
    const bool one = static_cast<std::size_t>(a.ndim()) == rank && same_shape(a, shape, 0);
    const bool many = static_cast<std::size_t>(a.ndim()) == rank + 1 && same_shape(a, shape, 1);
    if (!one && !many) {
      std::vector<py::ssize_t> given(a.shape(), a.shape() + a.ndim());
      throw py::value_error(function_ + ": " + name + " must have shape " + shape_text(shape) + " or " +
                            shape_text(shape, true) + " (a batch of N), not " + shape_text(given));
    }
    if (many) {
      if (states_ >= 0 && a.shape(0) != states_)
        throw py::value_error(function_ + ": " + name + " holds " + std::to_string(a.shape(0)) + " states, but " +
                              batch_source_ + " holds " + std::to_string(states_) +
                              " (every batched argument needs the same N)");
      states_ = a.shape(0);
      batch_source_ = name;
    }
    inputs_.push_back({std::move(a), many, size_of(shape)});
    return static_cast<int>(inputs_.size()) - 1;
  }

  /// The output `name` of shape `shape` (with the batch dimension when an input had one); returns
  /// its index for State::out.
  int output(std::vector<py::ssize_t> shape) {
    const py::ssize_t size = size_of(shape);
    if (states_ >= 0) shape.insert(shape.begin(), states_);
    outputs_.push_back({Array(shape), true, size});
    return static_cast<int>(outputs_.size()) - 1;
  }

  /// Where one state's arrays start.
  class State {
   public:
    const double* in(int k) const {
      const Pointer<const double>& p = call_.in_[static_cast<std::size_t>(k)];
      return p.base + state_ * p.stride;
    }
    double* out(int k) const {
      const Pointer<double>& p = call_.out_[static_cast<std::size_t>(k)];
      return p.base + state_ * p.stride;
    }

   private:
    friend class Call;
    State(const Call& call, py::ssize_t state) : call_(call), state_(state) {}
    const Call& call_;
    py::ssize_t state_;
  };

  /// f(state) for each state (one when nothing was batched), without the GIL: the generated
  /// functions keep no state and touch no Python object, and the arrays' addresses are taken
  /// before it is released.
  template <typename F> void run(F&& f) {
    const py::ssize_t n = states_ >= 0 ? states_ : 1;
    in_.clear();
    out_.clear();
    for (const Argument& a : inputs_) in_.push_back({a.array.data(), a.batched ? a.size : 0});
    for (Argument& a : outputs_) out_.push_back({a.array.mutable_data(), a.size});
    py::gil_scoped_release release;
    for (py::ssize_t s = 0; s < n; ++s) f(State(*this, s));
  }

  /// One group of W states in the batch functions' layout: in(k)[i][w] is entry i of input k for
  /// the group's state w, out(k) alike.
  template <int W> class Lanes {
   public:
    using In = const double (*)[W];
    using Out = double (*)[W];
    In in(int k) const { return reinterpret_cast<In>(call_.lane_in_[static_cast<std::size_t>(k)].data()); }
    Out out(int k) const { return reinterpret_cast<Out>(call_.lane_out_[static_cast<std::size_t>(k)].data()); }

   private:
    friend class Call;
    explicit Lanes(Call& call) : call_(call) {}
    Call& call_;
  };

  /// run(one), but W states at a time through batch(Lanes<W>) where a batch has W states or
  /// more: the groups' inputs are gathered (an unbatched input repeated in every lane) and their
  /// outputs scattered; the remaining states go through one(State).
  template <int W, typename One, typename Batch> void run_lanes(One&& one, Batch&& batch) {
    const py::ssize_t n = states_ >= 0 ? states_ : 1;
    if (n < W) return run(std::forward<One>(one));
    in_.clear();
    out_.clear();
    lane_in_.clear();
    lane_out_.clear();
    for (const Argument& a : inputs_) {
      in_.push_back({a.array.data(), a.batched ? a.size : 0});
      lane_in_.emplace_back(static_cast<std::size_t>(a.size * W));
    }
    for (Argument& a : outputs_) {
      out_.push_back({a.array.mutable_data(), a.size});
      lane_out_.emplace_back(static_cast<std::size_t>(a.size * W));
    }
    py::gil_scoped_release release;
    const py::ssize_t groups = n / W;
    const Lanes<W> lanes(*this);
    for (py::ssize_t g = 0; g < groups; ++g) {
      for (std::size_t k = 0; k < in_.size(); ++k) {
        const py::ssize_t size = inputs_[k].size;
        double* to = lane_in_[k].data();
        for (int w = 0; w < W; ++w) {
          const double* from = in_[k].base + (g * W + w) * in_[k].stride;
          for (py::ssize_t i = 0; i < size; ++i) to[i * W + w] = from[i];
        }
      }
      batch(lanes);
      for (std::size_t k = 0; k < out_.size(); ++k) {
        const py::ssize_t size = outputs_[k].size;
        const double* from = lane_out_[k].data();
        for (int w = 0; w < W; ++w) {
          double* to = out_[k].base + (g * W + w) * out_[k].stride;
          for (py::ssize_t i = 0; i < size; ++i) to[i] = from[i * W + w];
        }
      }
    }
    for (py::ssize_t s = groups * W; s < n; ++s) one(State(*this, s));
  }

  /// The outputs: the array itself for one, else a tuple in the declared order.
  py::object result() {
    if (outputs_.size() == 1) return std::move(outputs_[0].array);
    py::tuple t(outputs_.size());
    for (std::size_t k = 0; k < outputs_.size(); ++k) t[k] = std::move(outputs_[k].array);
    return std::move(t);
  }

  /// For the functions of one state (closure_positions, self_distances_near): a batched input
  /// is a ValueError.
  void require_one_state() const {
    if (states_ >= 0)
      throw py::value_error(function_ + " takes one state at a time: " + batch_source_ + " has a batch dimension");
  }

  /// N, or -1 when no input had a batch dimension.
  py::ssize_t states() const { return states_; }

 private:
  template <typename T> struct Pointer {
    T* base;
    py::ssize_t stride;  ///< entries from one state to the next (0: the same for every state)
  };
  struct Argument {
    Array array;
    bool batched;
    py::ssize_t size;  ///< entries of one state
  };

  Array convert(const char* name, const py::handle& object) const {
    if (object.is_none()) throw py::type_error(function_ + ": " + name + " is None (an array of float64 is expected)");
    Array a = Array::ensure(object);
    if (!a) {
      PyErr_Clear();
      throw py::type_error(function_ + ": " + name + " must be an array of numbers (float64), not " +
                           std::string(py::str(py::type::handle_of(object).attr("__name__"))));
    }
    return a;
  }

  static bool same_shape(const Array& a, const std::vector<py::ssize_t>& shape, int first) {
    for (std::size_t i = 0; i < shape.size(); ++i)
      if (a.shape(static_cast<py::ssize_t>(i) + first) != shape[i]) return false;
    return true;
  }

  static py::ssize_t size_of(const std::vector<py::ssize_t>& shape) {
    py::ssize_t n = 1;
    for (py::ssize_t s : shape) n *= s;
    return n;
  }

  std::string function_;
  std::vector<Argument> inputs_, outputs_;
  std::vector<Pointer<const double>> in_;
  std::vector<Pointer<double>> out_;
  std::vector<std::vector<double>> lane_in_, lane_out_;  ///< run_lanes: one group's arrays, W lanes each
  py::ssize_t states_ = -1;
  std::string batch_source_;
};

/// A C++ table of names as a Python list (the first `count` entries: the generated tables hold one
/// placeholder entry when they are empty).
template <std::size_t N> py::list names(const char* const (&table)[N], int count) {
  py::list out;
  for (int k = 0; k < count && static_cast<std::size_t>(k) < N; ++k) out.append(table[k]);
  return out;
}

/// Every entry of a C++ table of names.
template <std::size_t N> py::list names(const char* const (&table)[N]) { return names(table, static_cast<int>(N)); }

/// The first `count` pairs of names of a table of pairs, as a list of tuples.
template <std::size_t N> py::list pairs(const char* const (&table)[N][2], int count) {
  py::list out;
  for (int k = 0; k < count && static_cast<std::size_t>(k) < N; ++k) out.append(py::make_tuple(table[k][0], table[k][1]));
  return out;
}

/// A C++ table of numbers as a NumPy array (the first `count` entries).
template <typename T, std::size_t N> py::array_t<T> numbers(const T (&table)[N], int count) {
  const py::ssize_t n = count < 0 ? 0 : static_cast<py::ssize_t>(std::min<std::size_t>(N, static_cast<std::size_t>(count)));
  py::array_t<T> out(n);
  for (py::ssize_t k = 0; k < n; ++k) out.mutable_data()[k] = table[k];
  return out;
}

}  // namespace mbgen::python
