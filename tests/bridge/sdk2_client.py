"""A low-level controller written against Unitree's own Python SDK (unitree_sdk2py, unmodified):
its channels, its message classes and its CRC (Unitree's native crc32_core). It does not know
it is talking to a simulator. Used by the test UnitreeSdk2ClientDrivesTheBridge.

    sdk2_client.py go|hg --domain D [--target Q] [--seconds S] [--extras]

Holds motor 0 (the chapter's pendulum hinge) at the target with kp 20, kd 2 and gravity
feed-forward m g d sin(q), answering every state with one command (a lockstep bridge advances
one period per command). Stops when the tick is --seconds past the first one. Prints the number of
states answered and the last q. With --extras it also listens, through the SDK's own classes,
to rt/sportmodestate, rt/secondary_imu (the family's IMUState_) and both wireless-controller
topics, and prints one line "extras {json}": how many of each arrived and the last of each, and
the keys of rt/lowstate's wireless_remote. Exit 0; 1 when no state came within 5 s.
"""
import json
import argparse
import math
import sys
import threading

from unitree_sdk2py.core.channel import (ChannelFactoryInitialize, ChannelPublisher,
                                         ChannelSubscriber)
from unitree_sdk2py.idl import default as sdk_default
from unitree_sdk2py.idl.unitree_go.msg.dds_ import LowCmd_ as GoLowCmd
from unitree_sdk2py.idl.unitree_go.msg.dds_ import IMUState_ as GoImuState
from unitree_sdk2py.idl.unitree_go.msg.dds_ import LowState_ as GoLowState
from unitree_sdk2py.idl.unitree_go.msg.dds_ import SportModeState_
from unitree_sdk2py.idl.unitree_go.msg.dds_ import WirelessController_
from unitree_sdk2py.idl.unitree_hg.msg.dds_ import IMUState_ as HgImuState
from unitree_sdk2py.idl.unitree_hg.msg.dds_ import LowCmd_ as HgLowCmd
from unitree_sdk2py.idl.unitree_hg.msg.dds_ import LowState_ as HgLowState
from unitree_sdk2py.utils.crc import CRC


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("family", choices=["go", "hg"])
    parser.add_argument("--domain", type=int, default=1)
    parser.add_argument("--target", type=float, default=0.5)
    parser.add_argument("--seconds", type=float, default=1.0)
    parser.add_argument("--extras", action="store_true")
    args = parser.parse_args()

    ChannelFactoryInitialize(args.domain, "lo")
    go = args.family == "go"
    publisher = ChannelPublisher("rt/lowcmd", GoLowCmd if go else HgLowCmd)
    publisher.Init()
    latest = {}
    arrived = threading.Condition()

    def on_state(state):
        with arrived:
            latest["state"] = state
            arrived.notify()

    subscriber = ChannelSubscriber("rt/lowstate", GoLowState if go else HgLowState)
    subscriber.Init(on_state, 10)
    crc = CRC()
    extras = {}
    keep = []  # the extra subscribers stay alive as long as the client

    def listen(topic, kind, summary):
        def on_message(message):
            with arrived:
                entry = extras.setdefault(topic, {"count": 0})
                entry["count"] += 1
                entry["last"] = summary(message)
        subscriber = ChannelSubscriber(topic, kind)
        subscriber.Init(on_message, 10)
        keep.append(subscriber)

    if args.extras:
        listen("rt/sportmodestate", SportModeState_, lambda m: {
            "stamp": m.stamp.sec + m.stamp.nanosec * 1e-9, "position": list(m.position),
            "velocity": list(m.velocity), "body_height": m.body_height,
            "imu_quaternion": list(m.imu_state.quaternion)})
        listen("rt/secondary_imu", GoImuState if go else HgImuState,
               lambda m: {"quaternion": list(m.quaternion), "gyroscope": list(m.gyroscope)})
        for topic in ("rt/wirelesscontroller", "rt/wireless_controller"):
            listen(topic, WirelessController_,
                   lambda m: {"lx": m.lx, "ly": m.ly, "rx": m.rx, "ry": m.ry, "keys": m.keys})
    remote_keys = 0

    answered = 0
    q = float("nan")
    first_tick = None
    while True:
        with arrived:
            if not arrived.wait_for(lambda: "state" in latest, timeout=5.0):
                print(f"sdk2_client: no state for 5 s (after {answered})", file=sys.stderr)
                return 0 if answered else 1
            state = latest.pop("state")
        q = state.motor_state[0].q
        remote_keys = state.wireless_remote[2] | state.wireless_remote[3] << 8
        # a robot's tick counts from its boot (ms): time is the tick less the first one's
        if first_tick is None:
            first_tick = state.tick
        if (state.tick - first_tick) / 1000.0 >= args.seconds:
            break
        if go:
            cmd = sdk_default.unitree_go_msg_dds__LowCmd_()
            cmd.head[0], cmd.head[1] = 0xFE, 0xEF
            cmd.level_flag = 0xFF
        else:
            cmd = sdk_default.unitree_hg_msg_dds__LowCmd_()
            cmd.mode_machine = state.mode_machine
        motor = cmd.motor_cmd[0]
        motor.mode = 1
        motor.q = args.target
        motor.dq = 0.0
        motor.kp = 20.0
        motor.kd = 2.0
        motor.tau = 1.0 * 9.81 * 0.5 * math.sin(args.target)
        cmd.crc = crc.Crc(cmd)
        publisher.Write(cmd)
        answered += 1
    print(f"sdk2_client: answered {answered} states, q {q:.4f}")
    if args.extras:
        with arrived:
            extras["rt/lowstate"] = {"wireless_remote_keys": remote_keys}
            print("extras " + json.dumps(extras))
    return 0


if __name__ == "__main__":
    sys.exit(main())
