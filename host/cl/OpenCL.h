// The Khronos C++ bindings, configured for OpenCL 1.2 with exceptions.
#pragma once

#define CL_HPP_TARGET_OPENCL_VERSION 120
#define CL_HPP_MINIMUM_OPENCL_VERSION 120
#define CL_HPP_ENABLE_EXCEPTIONS
#include <CL/opencl.hpp>

#include <string>

namespace wv {

// "CL_OUT_OF_RESOURCES (-5)" for an OpenCL error code.
std::string clErrorName(cl_int code);

} // namespace wv
