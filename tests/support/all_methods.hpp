// Every fixed-step method of the generated list (numerics/method_list.hpp) as GoogleTest's type
// list: the typed tests run on a new method as soon as its file exists, and fail to compile
// until the test's per-method expectations (Traits, Expected, Limit) name it too. They test what
// a fixed step h does (order at h → 0, stability limit in h, H over 10⁴ steps); an adaptive
// method (description.adaptive: dop853) has its own tests (test_dop853.cpp).
#pragma once

#include <gtest/gtest.h>

#include <type_traits>

#include "numerics/method_list.hpp"

namespace cs::test {

template <class List, class... Kept>
struct GTestTypesOf;
template <class... Kept>
struct GTestTypesOf<MethodList<>, Kept...> {
  using type = ::testing::Types<Kept...>;
};
template <class First, class... Rest, class... Kept>
struct GTestTypesOf<MethodList<First, Rest...>, Kept...> {
  using type = std::conditional_t<
      adaptive_method<First>(), typename GTestTypesOf<MethodList<Rest...>, Kept...>::type,
      typename GTestTypesOf<MethodList<Rest...>, Kept..., First>::type>;
};

using AllMethods = GTestTypesOf<Methods>::type;

}  // namespace cs::test
