// fq statuses as Python exceptions, carrying fq's one-line message.
#pragma once

#include "common/status.h"

namespace fq::py {

/// Engine and argument failures: bad parameters or mesh -> ValueError; an unavailable
/// engine or an internal fault -> RuntimeError. Does nothing for an ok status.
void throw_if_error(const Status& s);

/// Mesh file failures: the file cannot be opened, read or written -> OSError; the content
/// cannot be decoded or is not a triangle mesh -> ValueError. Does nothing for ok.
void throw_if_file_error(const Status& s);

}  // namespace fq::py
