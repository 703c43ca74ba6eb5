package io.stridekit.android.common

import java.nio.ByteBuffer
import java.nio.ByteOrder

/**
 * A growable buffer of fixed-size little-endian records: the packed layouts the
 * stridekit `push…Packed` methods take (one ByteArray copy across the FFI instead of a
 * list of records). Not thread-safe: the sessions use it under their lock.
 */
class PackedBuffer(val recordBytes: Int, initialRecords: Int = 64) {
    init {
        require(recordBytes > 0 && recordBytes % 8 == 0) { "records are whole f64/u64 fields" }
    }

    private var buf: ByteBuffer = ByteBuffer.allocate(recordBytes * maxOf(1, initialRecords)).order(ByteOrder.LITTLE_ENDIAN)
    private var open = false

    /** Complete records in the buffer. */
    val size: Int get() = buf.position() / recordBytes

    fun isEmpty(): Boolean = buf.position() == 0

    /** Start a record; follow with exactly `recordBytes / 8` puts. */
    fun begin(): PackedBuffer {
        check(!open && buf.position() % recordBytes == 0) { "previous record incomplete" }
        if (buf.remaining() < recordBytes) {
            val bigger = ByteBuffer.allocate(buf.capacity() * 2).order(ByteOrder.LITTLE_ENDIAN)
            buf.flip()
            bigger.put(buf)
            buf = bigger
        }
        open = true
        return this
    }

    fun f64(v: Double): PackedBuffer { buf.putDouble(v); return this }

    /** An optional field: null is encoded as NaN, as the layouts specify. */
    fun f64OrNaN(v: Double?): PackedBuffer { buf.putDouble(v ?: Double.NaN); return this }

    fun u64(v: Long): PackedBuffer { buf.putLong(v); return this }

    /** End a record (checks it has the right length). */
    fun end() {
        check(open && buf.position() % recordBytes == 0) { "record is not $recordBytes bytes" }
        open = false
    }

    /** The records so far as one array; the buffer is emptied. */
    fun drain(): ByteArray {
        check(!open) { "record incomplete" }
        val out = ByteArray(buf.position())
        buf.flip()
        buf.get(out)
        buf.clear()
        return out
    }

    companion object {
        /** `t_s, steps` (f64, i64 ≥ 0): `PaceTracker.pushStepCountsPacked`. */
        const val STEP_COUNT_BYTES = 16
        /** `t_s, ax, ay, az`: `PaceTracker.pushAccelPacked`, `PlacementClassifier.pushAccelPacked`. */
        const val ACCEL_BYTES = 32
        /** `t_s, lat, lon, alt, hAcc, speed, speedAcc` (NaN = absent): `PaceTracker.pushFixesPacked`. */
        const val FIX_BYTES = 56
        /** `t_s, accel xyz, gyro xyz, mag xyz` (mag NaN = none): `pushImuPacked` of `PhoneNavigator`, `PhoneOdometry`, `OrientationFilter`. */
        const val IMU_BYTES = 80
        /** `t_s` (f64), `sensor_type` (i64, Android `Sensor.TYPE_*`), `x, y, z` (f64): `PhoneNavigator.pushSensorEventsPacked`. */
        const val SENSOR_EVENT_BYTES = 40
        /** `Sensor.TYPE_ACCELEROMETER`, `TYPE_MAGNETIC_FIELD`, `TYPE_GYROSCOPE` (the codes of the 40-byte events). */
        const val TYPE_ACCELEROMETER = 1L
        const val TYPE_MAGNETIC_FIELD = 2L
        const val TYPE_GYROSCOPE = 4L
    }
}

/**
 * One location update, in the units stridekit takes (Android's Location maps 1:1;
 * absent optionals are null). `elapsedNs` is `Location.elapsedRealtimeNanos`, never
 * `Location.time` (wall clock, can jump).
 */
data class LocationSample(
    val elapsedNs: Long,
    val latDeg: Double,
    val lonDeg: Double,
    val altM: Double? = null,
    val horizontalAccuracyM: Double? = null,
    val speedMps: Double? = null,
    val speedAccuracyMps: Double? = null,
)

/**
 * Drops samples whose time does not increase (stridekit rejects them anyway; a
 * sensor HAL can deliver duplicates after a batch FIFO flush).
 */
class Monotonic {
    var last: Double = Double.NEGATIVE_INFINITY
        private set
    var dropped: Long = 0
        private set

    fun accept(tS: Double): Boolean {
        if (tS > last) { last = tS; return true }
        dropped++
        return false
    }
}

/** Packs accelerometer samples (32-byte records). */
class AccelBatcher {
    val buffer = PackedBuffer(PackedBuffer.ACCEL_BYTES)
    val order = Monotonic()

    fun add(tS: Double, x: Double, y: Double, z: Double): Boolean {
        if (!order.accept(tS)) return false
        buffer.begin().f64(tS).f64(x).f64(y).f64(z).end()
        return true
    }
}

/** Packs cumulative step counts (16-byte records). */
class StepCountBatcher {
    val buffer = PackedBuffer(PackedBuffer.STEP_COUNT_BYTES)
    val order = Monotonic()

    fun add(tS: Double, steps: Long): Boolean {
        require(steps >= 0) { "step counts are never negative" }
        if (!order.accept(tS)) return false
        buffer.begin().f64(tS).u64(steps).end()
        return true
    }
}

/**
 * Packs separate accelerometer, gyroscope and magnetometer events as they arrive
 * (40-byte records) for `PhoneNavigator.pushSensorEventsPacked`, which merges them
 * by the SDK's one rule (stridekit_core::imu: the same as `stridekit pdr` reading an
 * Android log). Each sensor's events must increase in time; an event that does not
 * is dropped here and counted per sensor (the navigator would refuse it).
 */
class SensorEventBatcher {
    val buffer = PackedBuffer(PackedBuffer.SENSOR_EVENT_BYTES, initialRecords = 256)
    private val accel = Monotonic()
    private val gyro = Monotonic()
    private val mag = Monotonic()

    /** Events dropped because their sensor's time did not increase. */
    val droppedOutOfOrder: Long get() = accel.dropped + gyro.dropped + mag.dropped

    fun add(tS: Double, sensorType: Long, x: Double, y: Double, z: Double): Boolean {
        val order = when (sensorType) {
            PackedBuffer.TYPE_ACCELEROMETER -> accel
            PackedBuffer.TYPE_GYROSCOPE -> gyro
            PackedBuffer.TYPE_MAGNETIC_FIELD -> mag
            else -> throw IllegalArgumentException("sensor type $sensorType: 1, 2 or 4")
        }
        if (!order.accept(tS)) return false
        buffer.begin().f64(tS).u64(sensorType).f64(x).f64(y).f64(z).end()
        return true
    }
}

/** Packs GNSS fixes (56-byte records). */
class FixBatcher {
    val buffer = PackedBuffer(PackedBuffer.FIX_BYTES, initialRecords = 4)
    val order = Monotonic()

    fun add(tS: Double, fix: LocationSample): Boolean {
        if (!order.accept(tS)) return false
        buffer.begin().f64(tS).f64(fix.latDeg).f64(fix.lonDeg).f64OrNaN(fix.altM)
            .f64OrNaN(fix.horizontalAccuracyM).f64OrNaN(fix.speedMps).f64OrNaN(fix.speedAccuracyMps).end()
        return true
    }
}
