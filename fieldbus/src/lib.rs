//! Packet-A I/O over Modbus TCP (client and HMI server) and CANopen (SocketCAN, virtual bus, cannelloni UDP).
