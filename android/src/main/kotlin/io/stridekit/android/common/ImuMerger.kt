package io.stridekit.android.common

/**
 * Merges the separate accelerometer, gyroscope and magnetometer event streams of
 * SensorManager into the 80-byte IMU records of `PhoneNavigator.pushImuPacked`
 * (`t_s, accel xyz m/s², gyro xyz rad/s, mag xyz µT`: the 9-axis layout of
 * `packImuSamples`).
 *
 * Android delivers each sensor on its own schedule, never in one event. The
 * accelerometer paces the output: each accelerometer sample becomes one record at its
 * own time, with the newest gyroscope sample (sample-and-hold; at most
 * [maxGyroAgeS] old, else the accelerometer sample is dropped and counted in
 * [droppedNoGyro]) and the newest magnetometer sample if at most [maxMagAgeS] old
 * (else NaN: no magnetometer). Hold error at 100–200 Hz: ≤ one gyro period (5–10 ms)
 * of rotation. Samples of a stream that do not advance in time are ignored.
 * Not thread-safe by itself: the sessions call it under their lock.
 */
class ImuMerger(
    val maxGyroAgeS: Double = 0.05,
    val maxMagAgeS: Double = 0.5,
) {
    val buffer = PackedBuffer(PackedBuffer.IMU_BYTES)
    private val out = Monotonic()
    private var gyroT = Double.NEGATIVE_INFINITY
    private val gyro = DoubleArray(3)
    private var magT = Double.NEGATIVE_INFINITY
    private val mag = DoubleArray(3)

    var droppedNoGyro: Long = 0
        private set

    /** Out-of-order or duplicate accelerometer samples ignored. */
    val droppedOutOfOrder: Long get() = out.dropped

    fun onGyro(tS: Double, x: Double, y: Double, z: Double) {
        if (tS <= gyroT) return
        gyroT = tS; gyro[0] = x; gyro[1] = y; gyro[2] = z
    }

    fun onMag(tS: Double, x: Double, y: Double, z: Double) {
        if (tS <= magT) return
        magT = tS; mag[0] = x; mag[1] = y; mag[2] = z
    }

    /** Returns true when a record was written. */
    fun onAccel(tS: Double, x: Double, y: Double, z: Double): Boolean {
        val gyroAge = tS - gyroT
        if (!(gyroAge <= maxGyroAgeS) || gyroAge < -maxGyroAgeS) {
            droppedNoGyro++
            return false
        }
        if (!out.accept(tS)) return false
        val magAge = tS - magT
        val hasMag = magAge <= maxMagAgeS && magAge >= -maxMagAgeS
        buffer.begin().f64(tS).f64(x).f64(y).f64(z).f64(gyro[0]).f64(gyro[1]).f64(gyro[2])
        if (hasMag) buffer.f64(mag[0]).f64(mag[1]).f64(mag[2]) else buffer.f64(Double.NaN).f64(Double.NaN).f64(Double.NaN)
        buffer.end()
        return true
    }
}
