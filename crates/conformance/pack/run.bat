@echo off
rem pointillist capture pack (docs/CONFORMANCE.md, "Check a Windows machine's hardware").
rem Replays the scenes in streams\ on this PC's Direct3D 9 with replayer.exe and keeps what it
rem drew in captures\ADAPTER-DRIVERVERSION-Windows_VERSION. It reads only this folder and
rem writes only captures\ inside it; it installs and changes nothing else.
rem Plain cmd.exe: no delayed expansion, no substrings in loops (Wine's cmd has neither).
setlocal EnableExtensions DisableDelayedExpansion
cd /d "%~dp0"
if not exist "replayer.exe" (
    echo The program replayer.exe is missing from this folder.
    echo It is built as source\BUILD.txt says, then put beside run.bat.
    goto :end
)
if not exist "streams\list.txt" (
    echo The folder "streams" is missing. If this folder came as a zip file,
    echo unzip it first ^(right-click the zip file, Extract All^) and run run.bat from there.
    goto :end
)
echo Drawing the test scenes with this PC's graphics card (Direct3D 9).
echo This usually takes a few minutes; the screen may flicker.
echo Please wait until this window says "Done".
if not exist "captures" mkdir "captures"
rem What an interrupted earlier run left: run.bat's own folder, replaced.
if exist "captures\running" rd /s /q "captures\running"
mkdir "captures\running"
if errorlevel 1 (
    echo Cannot create the folder captures\running here: copy this folder somewhere you can
    echo write, such as the Desktop or Documents, and run run.bat there.
    goto :end
)
pushd streams
..\replayer.exe ..\captures\running @list.txt > ..\captures\running\replayer.log 2>&1
set "STATUS=%ERRORLEVEL%"
popd
ver > "captures\running\windows.txt"

rem The name: the adapter's description and driver version from device.txt, and the Windows
rem version from `ver` ("Microsoft Windows [Version 10.0.19045.3803]": its last word).
set "ADAPTER=unknown adapter"
set "DRIVER=unknown driver"
set "WINVER=unknown"
if exist "captures\running\device.txt" (
    for /f "usebackq tokens=1,* delims==" %%a in ("captures\running\device.txt") do (
        if "%%a"=="description" set "ADAPTER=%%b"
        if "%%a"=="driver_version" set "DRIVER=%%b"
    )
)
set "VERLINE="
for /f "delims=" %%v in ('ver') do set "VERLINE=%%v"
if defined VERLINE for %%w in (%VERLINE:]=%) do set "WINVER=%%w"
if not defined ADAPTER set "ADAPTER=unknown adapter"
set "ADAPTER=%ADAPTER:"=%"
set "ADAPTER=%ADAPTER:~0,80%"
set "REST=%ADAPTER%-%DRIVER%-Windows_%WINVER%"
rem Every run of characters a file name cannot hold, or a command line would misread (spaces
rem included), becomes one "_".
set "NAME="
:clean
if not defined REST goto :cleaned
set "NEXT="
for /f "tokens=1,* delims=\/:*?<>|&%%^'(),;=!@ " %%a in ("%REST%") do (
    if defined NAME (set "NAME=%NAME%_%%a") else set "NAME=%%a"
    set "NEXT=%%b"
)
set "REST=%NEXT%"
goto :clean
:cleaned
if not defined NAME set "NAME=capture"
set "FINAL=%NAME%"
set /a N=1
:unique
if not exist "captures\%FINAL%" goto :unique_found
set /a N+=1
set "FINAL=%NAME%-%N%"
goto :unique
:unique_found
ren "captures\running" "%FINAL%"
if errorlevel 1 set "FINAL=running"
echo.
if not "%STATUS%"=="0" (
    echo The graphics card could not be tested ^(the replayer ended with status %STATUS%^).
    echo Please send the folder captures\%FINAL% anyway: its file replayer.log says why.
) else (
    echo Done. The results are in the folder captures\%FINAL%
)
echo To send it: right-click that folder, choose "Send to", then "Compressed (zipped) folder"
echo (on Windows 11: "Compress to ZIP file"), and send the .zip file back.
:end
echo.
if /i not "%~1"=="/nopause" pause
endlocal
