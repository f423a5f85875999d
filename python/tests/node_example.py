"""A ROS 2-style node that feeds the runtime monitor: one callback per message, a brake
command the moment the monitor reports a violated premise. It runs without ROS: in a real
node, `on_message` is the subscription callback for the fused robot/obstacle state and
`command` publishes to the controller (e.g. a std_msgs/String or a custom stop service).

    cert = safereach.Certificate.from_json(open("cert.json").read())
    node = MonitorNode(cert)
    # rclpy: self.create_subscription(State, "/safereach/state", lambda m: node.on_message(
    #     m.t, m.robot_x, m.robot_v, m.obstacle_x, m.obstacle_v, m.obstacle_id), 10)
"""

import safereach


class MonitorNode:
    """Checks every message against the certificate's premises; latches a brake command."""

    def __init__(self, certificate, command=None):
        self.monitor = safereach.Monitor(certificate)
        self.commanded = "drive"
        self.first_violation = None
        self._command = command or (lambda action: None)

    def on_message(self, t, robot_x, robot_v, obstacle_x, obstacle_v=None, obstacle_id=0):
        verdict, events = self.monitor.observe(t, robot_x, robot_v, obstacle_x,
                                               obstacle_v=obstacle_v, obstacle_id=obstacle_id)
        if events and self.first_violation is None:
            self.first_violation = events[0]
        if verdict == "violated" and self.commanded != "brake":
            # The certificate no longer covers this run: enter the passive-safe state.
            self.commanded = "brake"
            self._command("brake")
        return verdict
