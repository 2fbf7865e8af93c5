#include "core/cancel_token.h"

namespace fq {
namespace {
thread_local const CancelToken* t_current = nullptr;
}  // namespace

const CancelToken* current_cancel_token() { return t_current; }

CancelScope::CancelScope(const CancelToken* token) : previous_(t_current) { t_current = token; }
CancelScope::~CancelScope() { t_current = previous_; }

}  // namespace fq
