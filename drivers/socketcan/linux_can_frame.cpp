#include "socketcan/linux_can_frame.hpp"

#include <algorithm>
#include <cstring>

namespace hrgbench::drivers::socketcan {

std::size_t ToLinuxFrame(const hw::CanFrame& frame, canfd_frame* out) noexcept {
  std::memset(out, 0, sizeof *out);
  out->can_id = frame.id;
  if (frame.extended) out->can_id |= CAN_EFF_FLAG;
  if (frame.remote) out->can_id |= CAN_RTR_FLAG;
  out->len = frame.length;
  if (!frame.remote) std::copy_n(frame.data.begin(), frame.length, out->data);
  if (!frame.fd) return kClassicMtu;
  out->flags = static_cast<std::uint8_t>(frame.bit_rate_switch ? CANFD_BRS : 0);
  return kFdMtu;
}

bool FromLinuxFrame(const canfd_frame& in, std::size_t bytes, hw::CanFrame* out) noexcept {
  if (bytes != kClassicMtu && bytes != kFdMtu) return false;
  const bool fd = bytes == kFdMtu;
  const std::uint8_t max_length = fd ? hw::CanFrame::kMaxFdLength : hw::CanFrame::kMaxClassicLength;
  if (in.len > max_length) return false;
  hw::CanFrame frame;
  frame.extended = (in.can_id & CAN_EFF_FLAG) != 0;
  frame.id = in.can_id & (frame.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  frame.error = (in.can_id & CAN_ERR_FLAG) != 0;
  if (frame.error) frame.id = in.can_id & CAN_ERR_MASK;
  frame.remote = !fd && (in.can_id & CAN_RTR_FLAG) != 0;
  frame.fd = fd;
  frame.bit_rate_switch = fd && (in.flags & CANFD_BRS) != 0;
  frame.length = in.len;
  if (!frame.remote) std::copy_n(in.data, in.len, frame.data.begin());
  *out = frame;
  return true;
}

}  // namespace hrgbench::drivers::socketcan
