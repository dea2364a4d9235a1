// Checking OpenCL return codes: every call goes through check(), which throws
// clpt::Error(ExitCode::Device) naming the call and the error ("clEnqueueNDRangeKernel: CL_OUT_OF_RESOURCES").
#pragma once

#include <CL/cl.h>

#include <string>

namespace clpt::cl {

const char* error_name(cl_int code);
void check(cl_int code, const char* what);

}  // namespace clpt::cl
