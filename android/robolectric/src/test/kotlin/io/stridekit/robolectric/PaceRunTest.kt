package io.stridekit.robolectric

import android.Manifest
import android.content.Context
import android.hardware.Sensor
import android.hardware.SensorManager
import android.location.Location
import android.location.LocationManager
import android.os.Looper
import io.stridekit.PaceEstimate
import io.stridekit.PaceTracker
import io.stridekit.android.StrideSensors
import io.stridekit.android.StrideSensors.Companion.toSample
import io.stridekit.android.common.PaceSession
import io.stridekit.android.common.SessionState
import kotlinx.coroutines.CoroutineScope
import kotlinx.coroutines.Dispatchers
import kotlinx.coroutines.Job
import kotlinx.coroutines.cancel
import kotlinx.coroutines.launch
import org.junit.Assert.assertEquals
import org.junit.Assert.assertFalse
import org.junit.Assert.assertTrue
import org.junit.Test
import org.junit.runner.RunWith
import org.robolectric.RobolectricTestRunner
import org.robolectric.RuntimeEnvironment
import org.robolectric.Shadows.shadowOf
import org.robolectric.annotation.Config
import org.robolectric.shadows.SensorEventBuilder
import org.robolectric.shadows.ShadowSensor
import org.robolectric.shadows.ShadowSystemClock
import java.util.concurrent.TimeUnit
import android.os.SystemClock
import java.io.File
import kotlin.math.abs
import kotlin.math.floor
import kotlin.math.roundToLong

/**
 * A real run (../shared/data/pace) as Android delivers it: its GNSS fixes as
 * Locations with `elapsedRealtimeNanos` through the shadow LocationManager, its
 * cadence as the TYPE_STEP_COUNTER events a phone would report (the cumulative count
 * the cadence adds up to), through StrideSensors into a PaceSession; the distance must
 * be what `stridekit pace` gives for the same fixes and counts. Also the step
 * counter across a reboot and a Location without `elapsedRealtimeNanos`.
 */
@RunWith(RobolectricTestRunner::class)
@Config(sdk = [35])
class PaceRunTest {
    private val context: Context get() = RuntimeEnvironment.getApplication()

    /** One record of the run: seconds since its first record, position, cumulative steps. */
    private class Rec(val tS: Double, val tUnixS: Double, val lat: Double?, val lon: Double?, val altM: Double?, val steps: Long)

    /**
     * The run's records; the step count is the cadence added up over time, as a step
     * counter reports it (whole steps).
     */
    private fun run(file: File): List<Rec> {
        val rows = Shared.csv(file)
        val t0 = rows.first().getValue("t_unix_s").toDouble()
        var total = 0.0
        var lastT = t0
        return rows.map { r ->
            val t = r.getValue("t_unix_s").toDouble()
            val spm = r["steps_per_min"]?.toDoubleOrNull() ?: 0.0
            total += spm * (t - lastT) / 60.0
            lastT = t
            Rec(t - t0, t, r["lat_deg"]?.toDoubleOrNull(), r["lon_deg"]?.toDoubleOrNull(), r["alt_m"]?.toDoubleOrNull(), floor(total).toLong())
        }
    }

    /** The same records as the CSV `stridekit pace` reads (`steps`: cumulative count). */
    private fun writeCsv(recs: List<Rec>, out: File) {
        val cell = { v: Double? -> v?.toString() ?: "" }
        out.writeText(buildString {
            append("t_unix_s,lat_deg,lon_deg,alt_m,steps\n")
            for (r in recs) append("${r.tUnixS},${cell(r.lat)},${cell(r.lon)},${cell(r.altM)},${r.steps}\n")
        })
    }

    private inner class App(val session: PaceSession) {
        val sensorManager = context.getSystemService(Context.SENSOR_SERVICE) as SensorManager
        val locationManager = context.getSystemService(Context.LOCATION_SERVICE) as LocationManager
        val sensors = StrideSensors(sensorManager, session)
        val estimates = mutableListOf<PaceEstimate>()
        private val scope = CoroutineScope(Dispatchers.Unconfined + Job())

        init {
            scope.launch { session.estimates.collect { estimates += it } }
            assertEquals(listOf(Sensor.TYPE_STEP_COUNTER), sensors.start(Sensor.TYPE_STEP_COUNTER))
            locationManager.requestLocationUpdates(LocationManager.GPS_PROVIDER, 1000L, 0f, sensors.locationListener, Looper.getMainLooper())
        }

        /** The records from the boot at `bootNs` before the first (elapsedRealtime). */
        fun deliver(recs: List<Rec>, elapsedNs: (Rec) -> Long, count: (Rec) -> Long = { it.steps }) {
            val counter = sensorManager.getDefaultSensor(Sensor.TYPE_STEP_COUNTER)!!
            for (r in recs) {
                val ns = elapsedNs(r)
                shadowOf(sensorManager).sendSensorEventToListeners(
                    SensorEventBuilder.newBuilder().setSensor(counter).setTimestamp(ns)
                        .setValues(floatArrayOf(count(r).toFloat())).build(),
                )
                if (r.lat != null && r.lon != null) {
                    val loc = Location(LocationManager.GPS_PROVIDER).apply {
                        latitude = r.lat
                        longitude = r.lon
                        r.altM?.let { altitude = it }
                        time = (r.tUnixS * 1000).roundToLong()
                        elapsedRealtimeNanos = ns
                    }
                    shadowOf(locationManager).simulateLocation(loc)
                    shadowOf(Looper.getMainLooper()).idle()
                }
            }
        }

        fun stop() {
            sensors.stop()
            locationManager.removeUpdates(sensors.locationListener)
            assertFalse("listeners unregistered on stop", shadowOf(sensorManager).hasListener(sensors))
            scope.cancel()
        }
    }

    private fun setUp() {
        val sm = context.getSystemService(Context.SENSOR_SERVICE) as SensorManager
        shadowOf(sm).addSensor(ShadowSensor.newInstance(Sensor.TYPE_STEP_COUNTER))
        shadowOf(RuntimeEnvironment.getApplication()).grantPermissions(Manifest.permission.ACCESS_FINE_LOCATION)
        val lm = context.getSystemService(Context.LOCATION_SERVICE) as LocationManager
        shadowOf(lm).setProviderEnabled(LocationManager.GPS_PROVIDER, true)
    }

    /** The first of the five runs of one runner (about 35 minutes, cadence every record). */
    private fun runFile(): File =
        Shared.folder("pace/csv").listFiles { f -> f.name.startsWith("runpandas_2020-12-") }!!.minBy { it.name }

    /** Since the run's first record, on a phone that booted then. */
    private fun ns(r: Rec): Long = (r.tS * 1e9).roundToLong()

    @Test
    fun `a real run through LocationManager and the step counter gives the distance stridekit pace gives`() {
        setUp()
        val recs = run(runFile())
        val dir = Shared.tempDir("pace")
        val input = dir.resolve("run_with_step_counts.csv")
        writeCsv(recs, input)
        val out = dir.resolve("pace.csv")
        val summary = Shared.run("pace", input.path, "--out", out.path)
        val rows = Shared.csv(out)
        PaceTracker.withDefaults().use { tracker ->
            val app = App(PaceSession(tracker))
            app.deliver(recs, ::ns)
            app.session.flush()
            app.stop()
            // The CLI writes one row per record; where a record has a step sample and a
            // fix at the same time, the row is the estimate after the step sample (the
            // fix's own is skipped as not later): its speed is the one before the fix,
            // its distance the same (no time passes between them). So the distance is
            // compared at every fix, to the CSV's precision; the speed is not.
            val byTime = rows.associateBy { it.getValue("t_s") }
            var matched = 0
            for (e in app.estimates) {
                val row = byTime[Shared.fmt(e.tS, 3)] ?: continue
                matched++
                assertEquals("distance at ${e.tS} s", row.getValue("distance_m"), Shared.fmt(e.distanceM, 2))
            }
            val fixes = recs.count { it.lat != null }
            assertEquals("one estimate per fix", fixes, app.estimates.size)
            assertTrue("estimates compared with the CLI's rows: $matched of $fixes fixes", matched >= fixes * 9 / 10)
            val final = tracker.estimate()!!
            assertTrue(summary, summary.contains("distance ${Shared.fmt(final.distanceM, 0)} m"))
            assertEquals("the last row", rows.last().getValue("distance_m"), Shared.fmt(final.distanceM, 2))
            assertEquals(0L, app.session.droppedOutOfOrder)
        }
    }

    @Test
    fun `the step counter and the clock continue across a reboot`() {
        setUp()
        val recs = run(runFile()).take(400)
        val (first, second) = recs.subList(0, 200) to recs.subList(200, 400)
        PaceTracker.withDefaults().use { tracker ->
            val app = App(PaceSession(tracker))
            app.session.clock.onBoot(BOOT_EPOCH_MS)
            app.deliver(first, ::ns)
            val saved = app.session.saveState().toBytes()
            app.stop()
            val before = tracker.estimate()!!
            // The phone reboots 60 s after the last record: elapsedRealtime and the step
            // counter start again from 0.
            val lastNs = ns(first.last())
            val newBootEpochMs = BOOT_EPOCH_MS + lastNs / 1_000_000 + 60_000
            val restored = PaceSession.restore(SessionState.fromBytes(saved))
            restored.tracker.use { t2 ->
                assertTrue("reboot detected", restored.clock.onBoot(newBootEpochMs))
                restored.stepCounter.onReboot()
                val app2 = App(restored)
                val base = second.first().steps
                val t0 = second.first().tS
                app2.deliver(second, { r -> ((r.tS - t0 + 1.0) * 1e9).roundToLong() }, { r -> r.steps - base })
                app2.stop()
                restored.flush()
                val after = t2.estimate()!!
                assertTrue("times go on: ${after.tS} > ${before.tS} + 60", after.tS > before.tS + 60.0)
                assertEquals("steps counted from the new boot", first.last().steps + (second.last().steps - base), restored.stepCounter.total)
                assertTrue("distance goes on", after.distanceM > before.distanceM + 100.0)
                assertEquals(0L, restored.droppedOutOfOrder)
                assertTrue("no rejections", app2.estimates.size >= second.count { it.lat != null } - 1)
            }
        }
    }

    @Test
    fun `a Location without elapsedRealtimeNanos is placed by its wall-clock age`() {
        // Robolectric's device booted 0.1 s ago: let it run a minute.
        ShadowSystemClock.advanceBy(60, TimeUnit.SECONDS)
        val now = SystemClock.elapsedRealtimeNanos()
        val loc = Location(LocationManager.GPS_PROVIDER).apply {
            latitude = 46.5
            longitude = 6.6
            time = System.currentTimeMillis() - 2_000
        }
        assertEquals(0L, loc.elapsedRealtimeNanos)
        // (Robolectric's SystemClock stands still; the wall clock runs: a second's slack.)
        val s = loc.toSample()
        assertTrue("2 s before now: ${(now - s.elapsedNs) / 1e6} ms", abs(now - 2_000_000_000L - s.elapsedNs) < 1_000_000_000L)
        assertEquals(null, s.horizontalAccuracyM)
        // Neither clock: at its arrival.
        val bare = Location(LocationManager.GPS_PROVIDER).apply { latitude = 1.0; longitude = 2.0 }
        assertTrue(bare.toSample().elapsedNs == SystemClock.elapsedRealtimeNanos())
        // With it: taken as it is.
        loc.elapsedRealtimeNanos = 123_456_789L
        assertEquals(123_456_789L, loc.toSample().elapsedNs)
    }

    private companion object {
        const val BOOT_EPOCH_MS = 1_606_900_000_000L
    }
}
