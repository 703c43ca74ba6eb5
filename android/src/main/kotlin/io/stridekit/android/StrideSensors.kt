package io.stridekit.android

import android.hardware.Sensor
import android.hardware.SensorEvent
import android.hardware.SensorEventListener
import android.hardware.SensorManager
import android.location.Location
import android.location.LocationListener
import android.os.Build
import android.os.Bundle
import android.os.Handler
import android.os.SystemClock
import io.stridekit.android.common.LocationSample
import io.stridekit.android.common.SensorSink

/**
 * Thin Android glue: SensorManager and LocationManager callbacks to a [SensorSink]
 * (`PaceSession`, `NavigatorSession` from `io.stridekit.android.common`). All the
 * logic (clock conversion, batching, merging, the Flow) is in the plain-Kotlin
 * `common` package, which the JVM host tests exercise; this file only copies fields.
 *
 * ```kotlin
 * val tracker = PaceTracker.withDefaults()
 * val session = PaceSession(tracker)
 * session.clock.onBoot(StrideSensors.bootEpochMs())
 * val sensors = StrideSensors(sensorManager, session)
 * sensors.start(Sensor.TYPE_STEP_COUNTER)                 // ACTIVITY_RECOGNITION permission
 * locationManager.requestLocationUpdates(LocationManager.GPS_PROVIDER, 1000L, 0f, sensors.locationListener)
 * scope.launch { session.estimates.collect { e -> show(e.paceSPerKm) } }
 * ```
 */
class StrideSensors(
    private val sensorManager: SensorManager,
    private val sink: SensorSink,
) : SensorEventListener {
    /**
     * Forward location updates (`Location.elapsedRealtimeNanos`, never `Location.time`).
     * All four methods are implemented: below API 29 the framework calls
     * onStatusChanged/onProviderEnabled/onProviderDisabled, and a lambda (only
     * onLocationChanged) would fail there with AbstractMethodError.
     */
    val locationListener: LocationListener = object : LocationListener {
        override fun onLocationChanged(location: Location) = sink.onLocation(location.toSample())

        @Deprecated("Deprecated in API 29")
        override fun onStatusChanged(provider: String?, status: Int, extras: Bundle?) {}

        override fun onProviderEnabled(provider: String) {}

        override fun onProviderDisabled(provider: String) {}
    }

    /**
     * Register for the given sensor types (Sensor.TYPE_ACCELEROMETER, TYPE_GYROSCOPE,
     * TYPE_MAGNETIC_FIELD, TYPE_STEP_COUNTER). `samplingPeriodUs` 10 000 = 100 Hz (every
     * engine; 40 000 = 25 Hz is enough for steps and dead reckoning and costs less
     * battery, the foot navigator wants 100 Hz or more: docs/api.md, "Sampling rates");
     * `maxReportLatencyUs` > 0 lets the sensor hub batch events while the screen is
     * off (the events keep their own timestamps). Returns the types that exist on this
     * device and were registered.
     */
    fun start(
        vararg types: Int,
        samplingPeriodUs: Int = 10_000,
        maxReportLatencyUs: Int = 0,
        handler: Handler? = null,
    ): List<Int> = types.filter { type ->
        val sensor = sensorManager.getDefaultSensor(type) ?: return@filter false
        // The step counter is on-change: the sampling period does not apply.
        val period = if (type == Sensor.TYPE_STEP_COUNTER) SensorManager.SENSOR_DELAY_NORMAL else samplingPeriodUs
        sensorManager.registerListener(this, sensor, period, maxReportLatencyUs, handler)
    }

    /**
     * Unregister every sensor (location updates: `locationManager.removeUpdates(locationListener)`).
     * Then `NavigatorSession.finish()` pushes what the event merge still holds back.
     */
    fun stop() = sensorManager.unregisterListener(this)

    override fun onSensorChanged(event: SensorEvent) {
        val v = event.values
        // SensorEvent.timestamp: nanoseconds on the elapsedRealtimeNanos clock.
        when (event.sensor.type) {
            Sensor.TYPE_ACCELEROMETER -> sink.onAccelerometer(event.timestamp, v[0], v[1], v[2])
            Sensor.TYPE_GYROSCOPE -> sink.onGyroscope(event.timestamp, v[0], v[1], v[2])
            Sensor.TYPE_MAGNETIC_FIELD -> sink.onMagneticField(event.timestamp, v[0], v[1], v[2])
            Sensor.TYPE_STEP_COUNTER -> sink.onStepCounter(event.timestamp, v[0])
        }
    }

    override fun onAccuracyChanged(sensor: Sensor, accuracy: Int) {}

    companion object {
        /** The wall-clock time of this boot, ms (for `SessionClock.onBoot`). */
        @JvmStatic
        fun bootEpochMs(): Long = System.currentTimeMillis() - SystemClock.elapsedRealtime()

        /**
         * When a Location was measured, on the elapsedRealtime clock (ns). Locations
         * from GNSS carry `elapsedRealtimeNanos`; one without it (0: a mock provider,
         * a Location built by hand or parcelled from old code) is placed by its
         * wall-clock age (`now − Location.time`), or at its arrival when it has no
         * time either, never in the future.
         */
        @JvmStatic
        fun Location.elapsedNanos(): Long {
            if (elapsedRealtimeNanos > 0L) return elapsedRealtimeNanos
            val now = SystemClock.elapsedRealtimeNanos()
            if (time <= 0L) return now
            val ageMs = (System.currentTimeMillis() - time).coerceAtLeast(0L)
            return (now - ageMs * 1_000_000L).coerceAtLeast(0L)
        }

        /** A Location in stridekit's units; absent optionals stay null. */
        @JvmStatic
        fun Location.toSample(): LocationSample = LocationSample(
            elapsedNs = elapsedNanos(),
            latDeg = latitude,
            lonDeg = longitude,
            altM = if (hasAltitude()) altitude else null,
            horizontalAccuracyM = if (hasAccuracy()) accuracy.toDouble() else null,
            speedMps = if (hasSpeed()) speed.toDouble() else null,
            speedAccuracyMps = if (Build.VERSION.SDK_INT >= Build.VERSION_CODES.O && hasSpeedAccuracy()) {
                speedAccuracyMetersPerSecond.toDouble()
            } else {
                null
            },
        )
    }
}
