//! Simulated phone IMU while walking/running (in progress).
